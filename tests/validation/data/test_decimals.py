"""Bulk decimal parsing of byte cells against the exact parser: bit for bit in every unit,
the schema's grammar (what it refuses), cells past the fast path, 64-bit integers."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from flexarm.validation.data.decimals import MAX_CELL, integers, reals, scan
from flexarm.validation.data.units import QUANTITIES, parse_values


def _buffer(texts: list[str]):
    encoded = [t.encode() for t in texts]
    ends = np.cumsum([len(b) + 1 for b in encoded]) - 1
    return np.frombuffer(b"|".join(encoded), np.uint8), ends - [len(b) for b in encoded], ends


def _exact(text: str, factor: Fraction) -> float:
    try:
        return float(parse_values([text], factor)[0])
    except OverflowError:
        return float("inf") if not text.startswith("-") else float("-inf")


@pytest.mark.parametrize("unit", ["m", "mm", "um", "kN", "deg", "mrad", "in", "Hz"])
def test_reals_are_bit_for_bit_the_exact_parser(unit):
    factor = next(f for units in QUANTITIES.values() for u, f in units.items() if u == unit)
    rng = np.random.default_rng(11)
    v = rng.normal(size=4000) * 10.0 ** rng.integers(-25, 25, 4000)
    texts = ([f"{x:.{d}f}" for x, d in zip(v[:1000], rng.integers(0, 14, 1000), strict=True)]
             + [repr(float(x)) for x in v[1000:2000]] + [f"{x:.{d}e}" for x, d in
                                                         zip(v[2000:3000], rng.integers(
                                                             0, 17, 1000), strict=True)]
             + [f"{x:.3E}".replace("E+", "E") for x in v[3000:]]
             + ["0", "-0", "+0.0", ".5", "5.", "-.5e-3", "1e400", "-1e-400", "9" * 30,
                "0." + "0" * 30 + "1", "1" * 19, "1" * 20 + ".5", "1e00005", "7" * (MAX_CELL + 5)])
    values, bad = reals(*_buffer(texts), factor)
    expected = np.array([_exact(t, factor) for t in texts])
    assert not bad.any()
    assert values.tobytes() == expected.tobytes()


@pytest.mark.parametrize("text", ["", "-", "+", ".", "e5", "1e", "1e+", "1.2.3", "+-1", "1-",
                                  "--1", "nan", "inf", "-inf", "1_0", "0x10", "1 2", "1e5.0",
                                  "1e5e5", "\u0661", "١.5", "1" * (MAX_CELL + 1) + "x"])
def test_what_is_not_a_plain_decimal(text):
    values, bad = reals(*_buffer(["1.5", text, "2"]), Fraction(1, 1000))
    assert bad.tolist() == [False, True, False] and values[[0, 2]].tolist() == [0.0015, 0.002]


def test_scan_gives_mantissa_and_exponent():
    m, k, negative, bad, exact = scan(*_buffer(["-12.50e3", "007", "1e-4", "1" * 25]))
    assert m[:3].tolist() == [1250, 7, 1] and k[:3].tolist() == [1, 0, -4]
    assert negative.tolist() == [True, False, False, False] and not bad.any()
    assert exact.tolist() == [True, True, True, False]  # 25 digits: read one by one


def test_integers_and_their_64_bit_range():
    texts = ["0", "-12", "+7", str(2**63 - 1), str(2**63), "1.0", "1e3", "9" * 25]
    values, bad = integers(*_buffer(texts))
    assert bad.tolist() == [False] * 4 + [True] * 4  # magnitudes below 2^63
    assert values[:4].tolist() == [0, -12, 7, 2**63 - 1]
