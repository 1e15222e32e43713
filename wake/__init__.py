"""wake: real-time pathological tremor extraction (WAKE)."""
