"""Tools around the simulator: the world demo, the benchmark, the colour calibration."""
