"""models/airframe."""
