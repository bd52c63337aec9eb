"""A long run in time pieces: their bounds, putting them together, the run they belong to.

A run of more than :data:`CHUNK_SAMPLES` samples is computed (and written) piece by piece, so
memory does not grow with its length; the engine (:mod:`aaria_pin.core.run.engine`) makes the
pieces, :func:`join_chunks` puts them together.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from aaria_pin.core.record import SERIES, TIMED_HARDWARE, RunRecord

__all__ = ["CHUNK_SAMPLES", "chunk_bounds", "join_chunks", "run_length"]

CHUNK_SAMPLES = 20_000
"""Samples per piece of a long run computed in time chunks (:func:`chunk_bounds`).

While a piece is computed the process holds about 4.6 kB per sample of it (5.7 kB with noise:
the record, the IMU kinematics, the noise, RNEA's work arrays) on top of about 235 MB of
imports and model (280 MB with noise when these figures were taken: scipy.signal, since
dropped). Measured on ``aaria-fig2`` at 100 kHz, 1 M samples (2 cores,
``benchmarks/bench_memory.py``'s child), peak RSS and wall time by piece length:

========= ================== ==================
piece     noise off          noise on
========= ================== ==================
10,000    283 MB, 4.0 s      344 MB, 10.3 s
20,000    328 MB, 4.8 s      402 MB, 9.9 s
50,000    465 MB, 4.9 s      570 MB, 9.3 s
100,000   681 MB, 5.7 s      979 MB, 9.6 s
========= ================== ==================

20,000 keeps a run of any length near 400 MB, well inside the 600 MB goal, at a speed within
the spread of these figures (the per-piece work outside the arrays is a few milliseconds);
50,000 would brush the goal with noise on. A run of at most this many samples is one piece:
computed and written whole, as before. With this length a 2 M-sample run peaks at 317 MB
(noise off) and 354 MB (noise on; 359 MB to a ``.mat`` v7.3), 3 to 15 MB above a
200,000-sample run (``benchmarks/bench_memory.py``; each piece makes its own sample times and
the noise's bias knots are drawn piece by piece, so nothing is held for the whole run).
"""


def chunk_bounds(samples: int, chunk: int | None = CHUNK_SAMPLES) -> list[tuple[int, int]]:
    """The pieces ``[(start, stop), ...]`` of a run of ``samples`` in chunks of ``chunk``.

    Args:
        samples: T, the run's number of samples
        chunk: samples per piece (the last may be shorter); None: one piece

    Raises:
        ParameterError: ``chunk`` < 1.
    """
    from aaria_pin.errors import ParameterError

    if chunk is None or samples <= chunk:
        return [(0, samples)]
    if chunk < 1:
        raise ParameterError(
            f"chunk is {chunk!r} samples; allowed: >= 1",
            parameter="chunk",
            value=chunk,
            allowed=">= 1",
        )
    return [(start, min(start + chunk, samples)) for start in range(0, samples, chunk)]


def run_length(record: RunRecord) -> int:
    """T, the samples of the whole run a record (or a piece of it) belongs to.

    From its ``duration`` [s] and ``rate`` [Hz] attributes (:func:`sampling_attributes`), as
    :func:`~aaria_pin.core.trajectory.sample_count` counts them; the record's own length if
    it has none.
    """
    from aaria_pin.core.trajectory import sample_count

    attributes = record.attributes
    if "duration" not in attributes or "rate" not in attributes:
        return record.n_samples
    return sample_count(float(attributes["duration"]), float(attributes["rate"]), None)


def join_chunks(chunks: Iterable[RunRecord]) -> RunRecord:
    """One record of a run from its pieces in time order (the last piece's other fields).

    A single piece is returned as it is; the attributes, tables, views and names come from
    the last piece, whose attributes cover the whole run (the tables of extra sensors and the
    joint channels' time-axis tables, which hold each piece's signals, are put together as the
    series are).
    """
    from dataclasses import replace

    pieces = list(chunks)
    if len(pieces) == 1:
        return pieces[0]
    series: dict[str, Any] = {
        name: np.concatenate([getattr(p, name) for p in pieces]) for name in SERIES
    }
    last = pieces[-1]
    sensors = last.attributes.get("sensors", {})  # a sensor's table is its piece's signals
    timed = [d["table"] for d in sensors.values()] + [n for n in TIMED_HARDWARE if n in last.tables]
    if timed:
        tables = dict(last.tables)
        for name in timed:
            tables[name] = np.concatenate([p.tables[name] for p in pieces])
        series["tables"] = tables
    return replace(last, **series)
