"""fmus."""
