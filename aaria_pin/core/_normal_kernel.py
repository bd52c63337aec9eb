"""The standard normals of numpy, bit for bit, at a quarter of their cost: a compiled ziggurat.

``Generator.standard_normal`` (numpy's 256-layer ziggurat over ``PCG64``) costs about 8 ns a
number on the project's machine, while the generator's raw 64-bit words cost 2 ns
(``bit_generator.random_raw``): numpy's loop calls the bit generator through a function pointer
for every word and does not pipeline. A run's IMU white noise is 840,000 numbers for 10,000
samples of 14 IMUs: 7 ms, about 0.9× Pinocchio's RNEA of the same run
(``benchmarks/bench_record.py``). :func:`standard_normal` runs numpy's own algorithm
(``random_standard_normal`` of numpy's ``distributions.c``, with its tables, which numba ships
as ``numba.np.random._constants``) in one compiled loop that steps ``PCG64`` itself (its
128-bit LCG through an LLVM ``i128`` multiply, then the XSL-RR output), from the state read
off the generator, and writes the advanced state back: 1.7 ms for those 840,000 numbers
(measured, one core), the very numbers numpy gives, and the generator left where numpy leaves
it. So no stream changes and every file re-makes bit for bit. Measured alternatives: raw
words drawn with ``random_raw`` and the ziggurat over them, the generator then set back and
advanced by the words used (``PCG64.advance``), 1.8 + 1.2 ms; the 128-bit product from four
32-bit ones instead of ``i128``, 2.4 ms. Only ``PCG64`` (``default_rng``'s) takes this path;
another bit generator, or a draw of fewer than :data:`_SMALL` numbers, is numpy's own.
``exp``/``log1p`` (the 1 % of draws that are rejected or in the tail) are the C library's in
both (compiled ``exact``, without fastmath); the tests hold the numbers and the state equal to
numpy's on millions of draws, tails included. Loading the two kernels from numba's disk cache
costs 5–17 ms once per process (measured on a loaded machine, after another kernel had loaded
numba's registries; their first compile about 1.5 s): a single 1,000-sample run does not win it
back (0.5 ms saved), a data set's worker (0.3 ms a run) or a run of 20,000 samples (8 ms) does.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba.core.extending import intrinsic

from aaria_pin.core._compile import kernel
from aaria_pin.core.se3 import Array

__all__ = ["standard_normal"]

_SMALL = 4096
"""Below this many numbers the fixed cost (state copies, a kernel call) is not worth it."""


def _mulhi(typingctx: Any, a: Any, b: Any) -> Any:  # pragma: no cover - compiled
    """The high 64 bits of the 128-bit product of two uint64 (an LLVM ``i128`` multiply)."""
    from llvmlite import ir
    from numba import types

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        wide = ir.IntType(128)
        product = builder.mul(builder.zext(args[0], wide), builder.zext(args[1], wide))
        return builder.trunc(builder.lshr(product, ir.Constant(wide, 64)), ir.IntType(64))

    return types.uint64(types.uint64, types.uint64), codegen


_mulhi = intrinsic(_mulhi)

_MULTIPLIER_HIGH = np.uint64(0x2360ED051FC65DA4)
_MULTIPLIER_LOW = np.uint64(0x4385DF649FCCF645)
"""PCG64's 128-bit LCG multiplier (numpy's ``PCG_DEFAULT_MULTIPLIER_128``), in halves."""


@kernel(exact=True)
def _pcg64(high, low, inc_high, inc_low):  # type: ignore[no-untyped-def]  # pragma: no cover
    """One step of numpy's ``PCG64``: the new state's halves and its 64-bit output.

    ``state = state·multiplier + increment`` (mod 2¹²⁸), then the XSL-RR output of the new
    state: ``(high ^ low)`` rotated right by the top 6 bits of ``high``.
    """
    new_low = low * _MULTIPLIER_LOW
    new_high = _mulhi(low, _MULTIPLIER_LOW) + high * _MULTIPLIER_LOW + low * _MULTIPLIER_HIGH
    low = new_low + inc_low
    high = new_high + inc_high + (np.uint64(1) if low < new_low else np.uint64(0))
    word = high ^ low
    turn = high >> np.uint64(58)
    return high, low, (word >> turn) | (word << ((np.uint64(64) - turn) & np.uint64(63)))


@kernel(exact=True)
def _ziggurat(  # type: ignore[no-untyped-def]  # pragma: no cover
    state, out, ki, wi, fi, tail, inverse_tail
):
    """Fill ``out`` with numpy's ``random_standard_normal`` of the ``PCG64`` state ``state``.

    ``state`` holds the state's and the increment's 64-bit halves (high, low, high, low);
    its first two are advanced past the words used.
    """
    scale = 1.0 / 9007199254740992.0  # next_double: the top 53 bits of a word
    high, low, inc_high, inc_low = state[0], state[1], state[2], state[3]
    i = 0
    while i < out.size:
        high, low, r = _pcg64(high, low, inc_high, inc_low)
        idx = r & np.uint64(0xFF)
        r = r >> np.uint64(8)
        rabs = (r >> np.uint64(1)) & np.uint64(0x000FFFFFFFFFFFFF)
        x = rabs * wi[idx]
        if r & np.uint64(1):
            x = -x
        if rabs < ki[idx]:
            out[i] = x
            i += 1
        elif idx == 0:  # the tail beyond `tail`
            while True:
                high, low, word = _pcg64(high, low, inc_high, inc_low)
                xx = -inverse_tail * np.log1p(-((word >> np.uint64(11)) * scale))
                high, low, word = _pcg64(high, low, inc_high, inc_low)
                yy = -np.log1p(-((word >> np.uint64(11)) * scale))
                if yy + yy > xx * xx:
                    out[i] = -(tail + xx) if (rabs >> np.uint64(8)) & np.uint64(1) else tail + xx
                    i += 1
                    break
        else:
            high, low, word = _pcg64(high, low, inc_high, inc_low)
            if (fi[idx - 1] - fi[idx]) * ((word >> np.uint64(11)) * scale) + fi[idx] < np.exp(
                -0.5 * x * x
            ):
                out[i] = x
                i += 1
    state[0] = high
    state[1] = low


_TABLES: list[object] = []


def _tables() -> list[object]:
    """The ziggurat's tables (``ki``, ``wi``, ``fi``, ``r``, ``1/r``) as numba ships them."""
    if not _TABLES:
        from numba.np.random import _constants as z

        _TABLES.extend(
            [
                np.asarray(z.ki_double, dtype=np.uint64),
                np.asarray(z.wi_double, dtype=np.float64),
                np.asarray(z.fi_double, dtype=np.float64),
                float(z.ziggurat_nor_r),
                float(z.ziggurat_nor_inv_r),
            ]
        )
    return _TABLES


def standard_normal(rng: np.random.Generator, shape: int | tuple[int, ...]) -> Array:
    """``rng.standard_normal(shape)``: the same numbers, the generator left in the same state.

    Args:
        rng: random number generator (its ``PCG64`` takes the compiled path)
        shape: the shape of the array drawn

    Returns:
        A new float64 array of standard normals.
    """
    out = np.empty(shape)
    bits = rng.bit_generator
    if type(bits) is not np.random.PCG64 or out.size < _SMALL:
        rng.standard_normal(out=out)
        return out
    with bits.lock:  # as numpy's draw holds it: threads sharing the generator take turns
        saved = bits.state
        words = saved["state"]
        mask = (1 << 64) - 1
        halves = [words["state"] >> 64, words["state"] & mask, words["inc"] >> 64]
        state = np.array([*halves, words["inc"] & mask], dtype=np.uint64)
        _ziggurat(state, out.reshape(-1), *_tables())
        words["state"] = (int(state[0]) << 64) | int(state[1])
        bits.state = saved
    return out
