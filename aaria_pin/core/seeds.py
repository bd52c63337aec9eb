"""Seeds of a run: the allowed range, the check, the named streams, how a run file records them.

:class:`RunSeeds` is the one place where a run's random streams are derived from its seed:
every other module asks it for a stream by name (``seeds.sequence("joints")``) instead of
assembling ``SeedSequence(seed, spawn_key=(...))`` from bare part numbers.

numpy is imported inside the functions, so the command line can read :data:`MAX_SEED` at
start-up for free.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from aaria_pin.core.arguments import checked
from aaria_pin.errors import ParameterError

if TYPE_CHECKING:
    import numpy as np

MAX_SEED = 2**63 - 1
"""Largest noise seed (it is stored as a 64-bit attribute)."""

DATASET_STREAMS = ("structure", "joints", "base", "noise", "sensor_errors", "hardware")
"""The streams of run k of a data set with seed S, in spawn-key order: stream ``name`` is
``SeedSequence(S, spawn_key=(k, DATASET_STREAMS.index(name)))``. The order is part of the file
format: every data set since 0.2 was drawn from it (``noise_stream`` 3 is stored in the file).
0.4 added ``sensor_errors`` (4: the parent of a run's sensor-error streams,
:func:`sensor_sequence`) and ``hardware`` (5: the run's draw of the configured hardware ranges)."""

SENSOR_PARTS = ("imu", "encoder", "torque_sensor", "actuator", "controller", "current_sensor")
"""The sensor-error streams of a run, children of its sensor seed (:func:`sensor_sequence`):
part ``name`` is spawn-key element ``SENSOR_PARTS.index(name)`` below it (file format)."""

SINGLE_STREAMS = {"fourier": 1}
"""The streams of a single run with ``--seed S`` beside its noise (``default_rng(S)``): stream
``name`` is ``SeedSequence(S, spawn_key=(SINGLE_STREAMS[name],))``."""


@checked
@dataclass(frozen=True)
class RunSeeds:
    """The named random streams of one run: the one place they are derived from its seed.

    A single run (``run`` None) draws its IMU noise from ``default_rng(seed)`` (the noise seed
    is the integer itself, as every run file since 0.1 records it) and its Fourier coefficients
    from ``SeedSequence(seed, spawn_key=(1,))``. Run k of a data set draws each part from its
    own stream, ``SeedSequence(seed, spawn_key=(k, part))`` (:data:`DATASET_STREAMS`), so
    keeping one part fixed leaves the draws of the others unchanged; a data set's Fourier
    coefficients come from its ``joints`` stream.

    Attributes:
        seed: the seed, 0 to 2⁶³ - 1
        run: the run's index in its data set (None: a single run)
        noise_part: the spawn-key part of a data set run's noise (3; files store it as
            ``noise_stream``)
    """

    seed: int
    run: int | None = None
    noise_part: int = DATASET_STREAMS.index("noise")

    def __post_init__(self) -> None:
        check_seed(self.seed)
        if self.run is not None and not (isinstance(self.run, int) and self.run >= 0):
            raise ParameterError(parameter="run", value=self.run, allowed="an integer >= 0")

    def sequence(self, stream: str) -> np.random.SeedSequence:
        """The ``SeedSequence`` of stream ``stream``.

        Args:
            stream: a name of :data:`DATASET_STREAMS` (or ``"fourier"``) for a data set's run;
                of :data:`SINGLE_STREAMS` or ``"noise"`` for a single run

        Raises:
            ParameterError: a stream the run does not have.
        """
        import numpy as np

        if self.run is None:
            if stream in SINGLE_STREAMS:
                return np.random.SeedSequence(self.seed, spawn_key=(SINGLE_STREAMS[stream],))
            if stream == "noise":
                return np.random.SeedSequence(self.seed)
            allowed = ", ".join([*SINGLE_STREAMS, "noise"])
        else:
            part = _dataset_part(stream, self.noise_part)
            if part is not None:
                return np.random.SeedSequence(self.seed, spawn_key=(self.run, part))
            allowed = ", ".join([*DATASET_STREAMS, "fourier"])
        raise ParameterError(parameter="stream", value=stream, allowed=allowed)

    def generator(self, stream: str) -> np.random.Generator:
        """A generator of stream ``stream`` (:meth:`sequence`)."""
        import numpy as np

        if self.run is None and stream == "noise":
            return np.random.default_rng(self.seed)
        return np.random.default_rng(self.sequence(stream))

    @property
    def noise(self) -> int | np.random.SeedSequence:
        """The seed of the run's IMU noise, as producers take it and run files record it."""
        return self.seed if self.run is None else self.sequence("noise")


def _dataset_part(stream: str, noise_part: int) -> int | None:
    """The spawn-key part of a data set run's stream (its Fourier is its ``joints`` stream)."""
    if stream == "noise":
        return noise_part
    if stream == "fourier":
        stream = "joints"
    return DATASET_STREAMS.index(stream) if stream in DATASET_STREAMS else None


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


SENSOR_SEED_PART = {"single": 2, "dataset": 4}
"""The spawn-key part of a run's sensor-error seed beside its noise seed: ``SeedSequence(S,
spawn_key=(2,))`` for a single run with seed S, ``SeedSequence(S, spawn_key=(k, 4))`` for run k of
a data set (its noise is part 3). New in 0.4: the IMU noise of earlier runs is unchanged, and a
run whose every new term is off draws nothing from it."""


def sensor_sequence(noise_seed: int | np.random.SeedSequence, part: str) -> np.random.SeedSequence:
    """The ``SeedSequence`` of a run's sensor-error stream ``part`` (:data:`SENSOR_PARTS`).

    Derived from the run's noise seed (which every run file records), so ``--from`` re-derives
    it: a single run's integer seed S gives ``SeedSequence(S, spawn_key=(2, i))``, a data set
    run's noise ``SeedSequence(S, spawn_key=(k, 3))`` gives ``SeedSequence(S, spawn_key=(k, 4, i))``
    with ``i = SENSOR_PARTS.index(part)``.

    Raises:
        ParameterError: an unknown part (parameter ``stream``).
    """
    import numpy as np

    if part not in SENSOR_PARTS:
        raise ParameterError(parameter="stream", value=part, allowed=", ".join(SENSOR_PARTS))
    index = SENSOR_PARTS.index(part)
    if isinstance(noise_seed, np.random.SeedSequence):
        key = tuple(noise_seed.spawn_key)
        head = key[:-1] if key else ()
        return np.random.SeedSequence(
            noise_seed.entropy, spawn_key=(*head, SENSOR_SEED_PART["dataset"], index)
        )
    check_seed(noise_seed)
    return np.random.SeedSequence(int(noise_seed), spawn_key=(SENSOR_SEED_PART["single"], index))
