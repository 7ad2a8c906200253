"""Heer's own quantities: the motor and transmission budget."""
