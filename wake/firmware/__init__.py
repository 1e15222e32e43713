"""Firmware tooling: C sources shipped with the package, header/source export, cost profiler."""
