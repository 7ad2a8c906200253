"""The emulator's model discrepancy: its effect registry and the engine run on the recordings."""
