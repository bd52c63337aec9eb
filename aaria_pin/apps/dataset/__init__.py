"""Data sets: many runs simulated in parallel into one HDF5 file.

One concept a module: :mod:`.spec_sources` (a spec from presets, files and flags),
:mod:`.spec` (what a data set holds; :mod:`.dh_spec` and :mod:`.urdf_spec` add the robot),
:mod:`.runs` (run k from its inputs, the one call into the run engine), :mod:`.job` (how it is
made: workers, resume, estimate, report), :mod:`.progress` (its estimate and progress shown),
:mod:`.generate` (the job into one file), :mod:`.runner` (local workers),
:mod:`.shards` (a Dask cluster), :mod:`.config` (the ranges and noise file), :mod:`.card` (the
data card).

The package exports the generator and its spec, each imported on first use (so importing one
module of the package, as the command line does, loads no other)::

    from aaria_pin.apps.dataset import DatasetSources, generate_dataset

    generate_dataset("ds.h5", DatasetSources(n_runs=4, preset="aaria-fig2").spec())
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from aaria_pin.core.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from aaria_pin.apps.dataset.generate import generate_dataset
    from aaria_pin.apps.dataset.job import DatasetJob, DatasetReport
    from aaria_pin.apps.dataset.spec import DatasetSettings, DatasetSpec
    from aaria_pin.apps.dataset.spec_sources import DatasetSources

_LAZY = {
    "generate_dataset": "aaria_pin.apps.dataset.generate",
    "DatasetJob": "aaria_pin.apps.dataset.job",
    "DatasetReport": "aaria_pin.apps.dataset.job",
    "DatasetSources": "aaria_pin.apps.dataset.spec_sources",
    "DatasetSettings": "aaria_pin.apps.dataset.spec",
    "DatasetSpec": "aaria_pin.apps.dataset.spec",
}

__all__ = [
    "DatasetJob",
    "DatasetReport",
    "DatasetSettings",
    "DatasetSources",
    "DatasetSpec",
    "generate_dataset",
]

__getattr__ = lazy_exports(__name__, _LAZY)
