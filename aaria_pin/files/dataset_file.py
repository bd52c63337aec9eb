"""The HDF5 file of a data set (layout: :mod:`aaria_pin.files.dataset`); kept importable here."""

from aaria_pin.files.dataset import *  # noqa: F403
from aaria_pin.files.dataset import __all__ as __all__
