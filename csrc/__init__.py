"""The C sources of wake, installed as package data (see wake.firmware.sources)."""
