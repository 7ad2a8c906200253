"""The emulator's figures and captions."""
