"""Data sets: many runs simulated in parallel into one HDF5 file.

One concept a module: :mod:`.spec_sources` (a spec from presets, files and flags),
:mod:`.spec` (what a data set holds; :mod:`.dh_spec` and :mod:`.urdf_spec` add the robot),
:mod:`.runs` (run k from its inputs, the one call into the run engine), :mod:`.job` (how it is
made: workers, resume, estimate, report), :mod:`.progress` (its estimate and progress shown),
:mod:`.generate` (the job into one file), :mod:`.runner` (local workers),
:mod:`.shards` (a Dask cluster), :mod:`.config` (the ranges and noise file), :mod:`.card` (the
data card).
"""
