"""Validation of the discrepancy engine on emulator recordings."""
