"""The analysis chain: the controller's filters, gait events, spring activity, energy per step and
the encoder against motion capture."""
