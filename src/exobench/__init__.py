"""exobench: reproducible bench tests of lower-limb exoskeletons."""

__version__ = "0.1.0"
