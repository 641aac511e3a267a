"""Post-processing: hysteresis loops and energy, damping identification, signals."""
