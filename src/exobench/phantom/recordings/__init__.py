"""Recordings in: C3D files read and checked, glitches screened, rates resampled."""
