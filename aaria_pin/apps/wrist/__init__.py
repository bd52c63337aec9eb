"""The spherical wrist of the wrist report: forward and inverse kinematics, workspace, runs."""
