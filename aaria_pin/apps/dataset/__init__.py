"""Data sets: many runs simulated in parallel into one HDF5 file.

One concept a module: :mod:`.sources` (a spec from presets, files and flags), :mod:`.spec`
(what a data set holds; :mod:`.dh` and :mod:`.urdf` add the robot), :mod:`.runs` (run k from
its inputs, the one call into the run engine), :mod:`.job` (how it is made: workers, resume,
estimate, report), :mod:`.engine` (the job into one file), :mod:`.runner` (local workers),
:mod:`.shards` (a Dask cluster), :mod:`.config` (the ranges and noise file), :mod:`.card` (the
data card).
"""
