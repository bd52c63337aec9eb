"""Data sets: many runs simulated in parallel into one HDF5 file."""
