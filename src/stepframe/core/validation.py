"""One validation per kind of parameter, each raising a one-line :class:`InputError`.

Every library entry point checks its parameters with these helpers, so the same kind of value is
refused the same way everywhere (DESIGN.md, reliability rules): a damping given as a percentage
gets the same hint in a frame file and on the command line, a count that would need more memory
than the machine has is refused before the allocation with the estimate in the message.

Each helper takes the parameter's user-facing name (``"xi_1"``, ``"--window-s"``) first and
returns the value converted to a plain Python ``float``/``int``.
"""

from __future__ import annotations

import math
import operator
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError

#: Largest seed numpy's generators accept (``SeedSequence`` takes any non-negative integer, but a
#: seed is written into result files and TOML, so it is kept within 64 bits).
MAX_SEED = 2**64 - 1


def _real(name: str, value: object) -> float:
    """``value`` as a float if it is a real number (bools and strings are not)."""
    if isinstance(value, bool | str | bytes) or value is None:
        raise InputError(f"{name} = {value!r}, expected a finite number")
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} = {_short(value)}, expected a finite number") from None
    return number


def finite(name: str, value: object) -> float:
    """A finite real number (any sign).

    Raises
    ------
    InputError
        ``value`` is not a real number, or is NaN or infinite.
    """
    number = _real(name, value)
    if not math.isfinite(number):
        raise InputError(f"{name} = {value!r}, expected a finite number")
    return number


def positive(name: str, value: object) -> float:
    """A finite number > 0."""
    number = finite(name, value)
    if not number > 0:
        raise InputError(f"{name} = {number!r}, expected > 0")
    return number


def non_negative(name: str, value: object) -> float:
    """A finite number ≥ 0."""
    number = finite(name, value)
    if not number >= 0:
        raise InputError(f"{name} = {number!r}, expected ≥ 0")
    return number


def in_range(
    name: str,
    value: object,
    low: float,
    high: float,
    *,
    low_open: bool = False,
    high_open: bool = False,
    unit: str = "",
) -> float:
    """A finite number in the interval from ``low`` to ``high``.

    Parameters
    ----------
    name
        The parameter's name for the message.
    value
        The value to check.
    low, high
        The bounds (in the parameter's own unit).
    low_open, high_open
        Whether each bound is excluded.
    unit
        The unit for the message (``"s"``, ``"Hz"``).
    """
    number = finite(name, value)
    below = operator.le if low_open else operator.lt
    above = operator.ge if high_open else operator.gt
    if below(number, low) or above(number, high):
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        suffix = f" {unit}" if unit else ""
        interval = f"{left}{low:g}, {high:g}{right}{suffix}"
        raise InputError(f"{name} = {number:g}{suffix}, expected a value in {interval}")
    return number


def damping_fraction(name: str, value: object, *, high: float = 1.0) -> float:
    """A damping ratio as a fraction in [0, high), with a hint when it looks like a percentage.

    Parameters
    ----------
    name
        The parameter's name.
    value
        The ratio.
    high
        Excluded upper bound: 1 (under-damped, every user-facing parameter) by default; a library
        object that also models over-damped systems passes a larger one.

    Raises
    ------
    InputError
        Not finite, negative, or ≥ ``high`` (``5`` says "a fraction: 5 % is 0.05").
    """
    number = finite(name, value)
    if number < 0:
        raise InputError(f"{name} = {number!r}, expected ≥ 0 (a damping fraction)")
    if number < high:
        return number
    hint = ""
    if 1 <= number <= 100:
        hint = f" (a fraction: {number:g} % is {number / 100:g})"
    raise InputError(f"{name} {number!r}, expected a damping fraction in [0, {high:g}){hint}")


def frequency(name: str, value: object, *, unit: str = "Hz", high: float = 1e4) -> float:
    """A frequency: finite, > 0 and at most ``high`` (default 10 kHz, far above any record)."""
    return in_range(name, value, 0.0, high, low_open=True, unit=unit)


def length(
    name: str, value: object, *, low: float = 0.0, high: float = 1e6, unit: str = "s"
) -> float:
    """A duration or length: finite, > ``low`` and at most ``high`` (default 10⁶ s, 11.6 days)."""
    return in_range(name, value, low, high, low_open=True, unit=unit)


def integer(name: str, value: object, *, low: int | None = None, high: int | None = None) -> int:
    """An integer (an integral float such as ``3.0`` is accepted) within optional bounds."""
    if isinstance(value, bool):
        raise InputError(f"{name} = {value!r}, expected an integer")
    if isinstance(value, int | np.integer):
        number = int(value)
    else:
        real = finite(name, value)
        if real != int(real):
            raise InputError(f"{name} = {value!r}, expected an integer")
        number = int(real)
    if (low is not None and number < low) or (high is not None and number > high):
        bounds = f"≥ {low}" if high is None else f"≤ {high}" if low is None else f"{low}..{high}"
        raise InputError(f"{name} = {number}, expected an integer {bounds}")
    return number


def count(
    name: str,
    value: object,
    *,
    bytes_each: float,
    low: int = 1,
    budget_bytes: float | None = None,
) -> int:
    """A count whose memory (``value × bytes_each``) must fit the budget.

    Parameters
    ----------
    name
        The parameter's name.
    value
        The count.
    bytes_each
        Memory one unit of the count costs [bytes] (e.g. 8 × samples per bootstrap replicate).
    low
        Smallest count accepted.
    budget_bytes
        Largest memory accepted [bytes] (default: the run's memory budget,
        :func:`stepframe.core.memory.budget_bytes`).

    Raises
    ------
    InputError
        Not an integer, below ``low``, or needing more than the budget (the one refusal of
        :func:`stepframe.core.memory.check_memory`, with the largest count that fits).
    """
    from stepframe.core.memory import budget_bytes as run_budget
    from stepframe.core.memory import check_memory

    number = integer(name, value, low=low)
    budget = run_budget() if budget_bytes is None else budget_bytes
    check_memory(
        float(number) * float(bytes_each),
        f"{name} = {number}",
        f"at most {int(budget // max(bytes_each, 1.0))}",
        budget=budget_bytes,
    )
    return number


def seed(name: str, value: object) -> int | None:
    """A random seed: None or an integer in [0, 2⁶⁴)."""
    if value is None:
        return None
    return integer(name, value, low=0, high=MAX_SEED)


def finite_array(
    name: str, values: ArrayLike, *, positive_values: bool = False, min_size: int = 1
) -> NDArray[np.float64]:
    """A 1-D float array of finite numbers (optionally all > 0) with at least ``min_size`` items."""
    try:
        array = np.atleast_1d(np.asarray(values, dtype=np.float64))
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} = {_short(values)}, expected numbers") from None
    if array.ndim != 1 or array.size < min_size:
        wanted = "a non-empty list" if min_size == 1 else f"a list of at least {min_size}"
        raise InputError(f"{name} of shape {array.shape}, expected {wanted} of numbers")
    if not np.all(np.isfinite(array)):
        raise InputError(f"{name} = {_short(values)}, expected finite numbers")
    if positive_values and not np.all(array > 0):
        raise InputError(f"{name} = {_short(values)}, expected positive numbers")
    return array


def _short(values: Any) -> str:
    text = repr(values)
    return text if len(text) <= 60 else text[:57] + "..."
