"""Reading and checking a lab's (or the twin's) emulator recordings against the contract."""
