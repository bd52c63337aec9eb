"""Data for machine learning: data set runs simulated inside the training loop.

A layer above :mod:`aaria_pin.apps` (it makes runs with the data set's spec) and below the
viewers and the command line. :class:`~.online.OnlineRuns` is a map-style dataset of a data
set's runs simulated on demand (run k the same, array for array, as run k of ``aaria dataset``
with the same settings); :meth:`OnlineRuns.windows <.online.OnlineRuns.windows>` gives
:class:`~.online.OnlineWindows`, an iterable dataset of their windows, split across PyTorch
``DataLoader`` workers. Torch is optional (the extra ``aaria-pin[ml]``): importing this package
never imports it; :meth:`OnlineWindows.torch <.online.OnlineWindows.torch>` wraps the windows in
a ``torch.utils.data.IterableDataset`` for a ``DataLoader``::

    from aaria_pin.ml import OnlineRuns

    runs = OnlineRuns.defaults(1000, seed=7)  # as aaria dataset -n 1000 --seed 7
    arrays = runs[3]  # run 3's stored arrays, simulated now
    for window in runs.windows(200, names=("imu", "link_types"), split="train"):
        pass  # window["imu"]: (200, 14, 6)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from aaria_pin.core.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from aaria_pin.ml.online import OnlineRuns, OnlineWindows, worker_info

_LAZY = {
    "OnlineRuns": "aaria_pin.ml.online",
    "OnlineWindows": "aaria_pin.ml.online",
    "worker_info": "aaria_pin.ml.online",
}

__all__ = ["OnlineRuns", "OnlineWindows", "worker_info"]

__getattr__ = lazy_exports(__name__, _LAZY)
