"""The online windows as a PyTorch ``IterableDataset`` (imported only when torch is wanted)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Protocol

import numpy as np
from torch.utils.data import IterableDataset

__all__ = ["TorchWindows"]


class OnlineWindows(Protocol):
    """What the wrapper uses of :class:`~.online.OnlineWindows` (not imported: no cycle)."""

    def __iter__(self) -> Iterator[dict[str, np.ndarray]]: ...

    def __len__(self) -> int: ...

    def set_epoch(self, epoch: int) -> None: ...


class TorchWindows(IterableDataset[dict[str, np.ndarray]]):
    """:class:`~.online.OnlineWindows` for a ``DataLoader``: each worker iterates its share.

    Args:
        windows: the windows

    Attributes:
        windows: as given
    """

    def __init__(self, windows: OnlineWindows) -> None:
        self.windows = windows

    def __iter__(self) -> Iterator[dict[str, np.ndarray]]:
        return iter(self.windows)

    def __len__(self) -> int:
        return len(self.windows)

    def set_epoch(self, epoch: int) -> None:
        """The windows' :meth:`~.online.OnlineWindows.set_epoch`."""
        self.windows.set_epoch(epoch)
