"""models/fcs."""
