"""The phantom's digital twin: programmed motion, mechanics, recordings and its calibration."""
