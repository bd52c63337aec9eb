"""The online windows as a PyTorch ``IterableDataset`` (imported only when torch is wanted)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Protocol

import numpy as np
from torch.utils.data import IterableDataset, get_worker_info

__all__ = ["TorchWindows"]


class OnlineWindows(Protocol):
    """What the wrapper uses of :class:`~.online.OnlineWindows` (not imported: no cycle)."""

    def __iter__(self) -> Iterator[dict[str, np.ndarray]]: ...

    def __len__(self) -> int: ...

    @property
    def epoch(self) -> int: ...

    def set_epoch(self, epoch: int) -> None: ...


class TorchWindows(IterableDataset[dict[str, np.ndarray]]):
    """:class:`~.online.OnlineWindows` for a ``DataLoader``: each worker iterates its share.

    With ``advance_epochs`` each iteration after the first in a ``DataLoader`` worker moves
    that worker's copy to the next epoch (fresh arms): what a ``DataLoader`` with
    ``persistent_workers=True`` needs, since its workers keep the copy they were given at the
    first epoch and never see a later :meth:`set_epoch` of the main process. Its workers each
    iterate once per epoch (the loader re-creates their iterators on each new epoch), so they
    move together. In the main process (no workers) nothing moves: :meth:`set_epoch` there, as
    without the option. Measured reason (``python benchmarks/bench_online.py``): a loader that
    starts its workers anew each epoch pays their start-up (about a third of a second each) per
    epoch.

    Args:
        windows: the windows
        advance_epochs: move to the next epoch at each iteration after the first

    Attributes:
        windows: as given (a worker's copy holds that worker's epoch)
        advance_epochs: as given
    """

    def __init__(self, windows: OnlineWindows, advance_epochs: bool = False) -> None:
        self.windows = windows
        self.advance_epochs = advance_epochs
        self._iterations = 0

    def __iter__(self) -> Iterator[dict[str, np.ndarray]]:
        if self.advance_epochs and get_worker_info() is not None:  # a worker's own copy only
            if self._iterations:
                self.windows.set_epoch(self.windows.epoch + 1)
            self._iterations += 1
        return iter(self.windows)

    def __len__(self) -> int:
        return len(self.windows)

    def set_epoch(self, epoch: int) -> None:
        """The windows' :meth:`~.online.OnlineWindows.set_epoch`."""
        self.windows.set_epoch(epoch)
