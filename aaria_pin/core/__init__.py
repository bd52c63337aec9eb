"""The core: any Pinocchio model with named sensor frames.

Robot descriptions and their URDF, models, trajectories, kinematics, dynamics, IMU noise and the run
record. It knows nothing of DH tables, the Aaria paper, files, pictures or the command line.
"""
