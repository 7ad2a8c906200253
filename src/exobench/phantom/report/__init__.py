"""Figures and captions of the phantom group."""
