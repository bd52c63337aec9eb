"""Noise seeds of a run: the allowed range, the check, and how a run file records them.

numpy is imported inside the functions, so the command line can read :data:`MAX_SEED` at
start-up for free.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from aaria_pin.errors import ParameterError

if TYPE_CHECKING:
    import numpy as np

MAX_SEED = 2**63 - 1
"""Largest noise seed (it is stored as a 64-bit attribute)."""


def check_seed(seed: int | np.random.SeedSequence) -> None:
    """Refuse a seed that is neither an integer from 0 to 2⁶³ - 1 nor a ``SeedSequence``."""
    import numpy as np

    if not (isinstance(seed, (int, np.integer)) and 0 <= seed <= MAX_SEED) and not isinstance(
        seed, np.random.SeedSequence
    ):
        raise ParameterError(
            parameter="seed", value=seed, allowed=f"an integer from 0 to {MAX_SEED}"
        )


def seed_attributes(seed: int | np.random.SeedSequence) -> dict[str, Any]:
    """``seed`` (and, for a data set's run, the spawn key of its noise stream)."""
    import numpy as np

    if isinstance(seed, np.random.SeedSequence):
        entropy = seed.entropy if isinstance(seed.entropy, int) else 0
        return {"seed": entropy, "noise_spawn_key": [int(k) for k in seed.spawn_key]}
    return {"seed": int(seed)}


def stored_seed(attributes: dict[str, Any]) -> int | np.random.SeedSequence:
    """The noise seed a run file's attributes record (inverse of :func:`seed_attributes`)."""
    import numpy as np

    seed = attributes.get("seed", 0)
    if isinstance(seed, float) and seed.is_integer():  # MATLAB saves numbers as doubles
        seed = int(seed)
    if "noise_spawn_key" in attributes:  # a run of a data set
        return np.random.SeedSequence(seed, spawn_key=tuple(attributes["noise_spawn_key"]))
    return int(seed)
