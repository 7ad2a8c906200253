"""The emulator's digital twin: gait, the real-time controller loop, the recordings it writes."""
