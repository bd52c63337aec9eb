"""Identification from a run's sensor data: the kinematic model from IMUs and encoders."""
