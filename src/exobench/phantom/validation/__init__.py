"""Validation of the discrepancy engine: the twin arm and the open-world arm."""
