"""The drop model of a gear unit: its force laws (compiled), optional effects, simulation,
calibration against the runs and synthetic campaigns."""
