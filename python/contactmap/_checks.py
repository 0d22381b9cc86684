"""The argument checks every public function runs before any work: a wrong type is a
``TypeError``, a wrong value a ``ValueError``, each message starting with the argument's name and
saying what was expected (``window_bp: expected a positive int or a list of positive ints, got
str``, ``ignore_diags: expected a non-negative int, got -1``).

Each check returns the value as the library takes it (an ``int``, a ``float``, a ``str`` ...).
Ints are Python or numpy ints, or floats with an integral value (``1e6``); ``bool`` is not an
int here. Numbers are ints or floats (numpy's too), never strings."""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np


def _type(value: Any) -> str:
    return type(value).__name__


def _as_list(value: Any) -> list[Any] | None:
    """The items of a list, tuple, array, Series or other iterable (not a str, bytes or
    mapping), or None for anything else."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
        return None
    if isinstance(value, np.ndarray) and value.ndim != 1:
        return None
    return list(value)


def _is_int(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def _int_kind(minimum: int | None, maximum: int | None = None) -> str:
    if minimum is None:
        kind = "an int"
    elif minimum == 0:
        kind = "a non-negative int"
    elif minimum == 1:
        kind = "a positive int"
    else:
        kind = f"an int >= {minimum}"
    return kind if maximum is None else f"{kind} <= {maximum}"


def integer(
    name: str,
    value: Any,
    minimum: int | None = None,
    maximum: int | None = None,
    none: bool = False,
) -> Any:
    """An int (within ``minimum..maximum``), or None when ``none``."""
    kind = _int_kind(minimum, maximum) + (" or None" if none else "")
    if value is None and none:
        return None
    if _is_int(value):
        number = int(value)
    elif is_number(value) and math.isfinite(value) and float(value).is_integer():
        number = int(value)
    elif is_number(value):
        raise ValueError(f"{name}: expected {kind}, got {value!r}")
    else:
        raise TypeError(f"{name}: expected {kind}, got {_type(value)}")
    if (minimum is not None and number < minimum) or (maximum is not None and number > maximum):
        raise ValueError(f"{name}: expected {kind}, got {value!r}")
    return number


def integers(
    name: str, value: Any, minimum: int | None = None, empty: bool = False
) -> list[int]:
    """An int or a list of ints (each at least ``minimum``; empty only when ``empty``)."""
    kind = _int_kind(minimum)
    what = f"{kind} or a list of {kind.split(' ', 1)[1]}s"
    if is_number(value):
        return [integer(name, value, minimum)]
    items = _as_list(value)
    if items is None:
        raise TypeError(f"{name}: expected {what}, got {_type(value)}")
    if not items and not empty:
        raise ValueError(f"{name}: expected {what}, got an empty list")
    out = []
    for k, item in enumerate(items):
        if not is_number(item):
            raise TypeError(f"{name}[{k}]: expected {kind}, got {_type(item)}")
        out.append(integer(f"{name}[{k}]", item, minimum))
    return out


def number(
    name: str,
    value: Any,
    minimum: float | None = None,
    maximum: float | None = None,
    above: float | None = None,
    below: float | None = None,
    none: bool = False,
) -> Any:
    """A finite number (``minimum <= value <= maximum``, ``above < value < below``), or None
    when ``none``."""
    bounds = []
    if minimum is not None:
        bounds.append(f">= {minimum}")
    if above is not None:
        bounds.append(f"> {above}")
    if maximum is not None:
        bounds.append(f"<= {maximum}")
    if below is not None:
        bounds.append(f"< {below}")
    if bounds == ["> 0"]:
        kind = "a positive number"
    elif bounds == [">= 0"]:
        kind = "a non-negative number"
    else:
        kind = "a number" + (" " + " and ".join(bounds) if bounds else "")
    if none:
        kind += " or None"
    if value is None and none:
        return None
    if not is_number(value):
        raise TypeError(f"{name}: expected {kind}, got {_type(value)}")
    x = float(value)
    if (
        not math.isfinite(x)
        or (minimum is not None and x < minimum)
        or (maximum is not None and x > maximum)
        or (above is not None and x <= above)
        or (below is not None and x >= below)
    ):
        raise ValueError(f"{name}: expected {kind}, got {value!r}")
    return x


def flag(name: str, value: Any, none: bool = False) -> Any:
    """True or False (numpy's too), or None when ``none``."""
    if value is None and none:
        return None
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    kind = "True or False" + (" or None" if none else "")
    raise TypeError(f"{name}: expected {kind}, got {_type(value)}")


def text(name: str, value: Any, choices: Sequence[str] | None = None, none: bool = False) -> Any:
    """A str (one of ``choices`` when given), or None when ``none``."""
    if value is None and none:
        return None
    listed = ", ".join(repr(c) for c in choices) if choices else ""
    kind = f"one of {listed}" if choices else "a str"
    if none:
        kind += " or None"
    if not isinstance(value, str):
        raise TypeError(f"{name}: expected {kind}, got {_type(value)}")
    if choices is not None and value not in choices:
        raise ValueError(f"{name}: expected {kind}, got {value!r}")
    return value


def texts(name: str, value: Any, none: bool = False) -> Any:
    """A str (one item) or a list of str, or None when ``none``."""
    if value is None and none:
        return None
    if isinstance(value, str):
        return [value]
    kind = "a str or a list of str" + (" or None" if none else "")
    items = _as_list(value)
    if items is None:
        raise TypeError(f"{name}: expected {kind}, got {_type(value)}")
    for k, item in enumerate(items):
        if not isinstance(item, str):
            raise TypeError(f"{name}[{k}]: expected a str, got {_type(item)}")
    return items


def path(name: str, value: Any, none: bool = False) -> Any:
    """A path (str or os.PathLike) as a str, or None when ``none``."""
    if value is None and none:
        return None
    if not isinstance(value, (str, os.PathLike)):
        kind = "a path (str or os.PathLike)" + (" or None" if none else "")
        raise TypeError(f"{name}: expected {kind}, got {_type(value)}")
    out = os.fspath(value)
    out = os.fsdecode(out) if isinstance(out, bytes) else out
    if not out:
        raise ValueError(f"{name}: expected a path, got an empty str")
    return out


def paths(name: str, value: Any) -> list[str]:
    """A path or a non-empty list of paths, as str."""
    if isinstance(value, (str, os.PathLike)):
        return [path(name, value)]
    items = _as_list(value)
    if items is None:
        raise TypeError(f"{name}: expected a path or a list of paths, got {_type(value)}")
    if not items:
        raise ValueError(f"{name}: expected a path or a list of paths, got an empty list")
    return [path(f"{name}[{k}]", item) for k, item in enumerate(items)]


def pair(name: str, value: Any, minimum: float | None = None, maximum: float | None = None) -> Any:
    """None, or (low, high): two numbers, low <= high (within minimum..maximum when given)."""
    if value is None:
        return None
    kind = "None or a pair of numbers (low, high)"
    items = _as_list(value)
    if items is None:
        raise TypeError(f"{name}: expected {kind}, got {_type(value)}")
    if len(items) != 2:
        raise ValueError(f"{name}: expected {kind}, got {len(items)} values")
    low = number(f"{name}[0]", items[0], minimum, maximum)
    high = number(f"{name}[1]", items[1], minimum, maximum)
    if low > high:
        raise ValueError(f"{name}: expected low <= high, got {tuple(items)!r}")
    return (low, high)


def frame(name: str, value: Any, columns: Sequence[str], note: str = "") -> Any:
    """A pandas DataFrame with ``columns`` (others allowed); ``note`` says more about them."""
    listed = " ".join(columns)
    if not hasattr(value, "columns") or not hasattr(value, "itertuples"):
        raise TypeError(
            f"{name}: expected a pandas DataFrame with columns {listed}{note}, got {_type(value)}"
        )
    have = [str(c) for c in value.columns]
    missing = [c for c in columns if c not in have]
    if missing:
        raise ValueError(
            f"{name}: missing columns {missing}: expected the columns {listed}{note}; it has "
            f"{have}"
        )
    return value


def column_values(name: str, values: Any, kind: str) -> np.ndarray:
    """A column's values as ``int64`` (``kind="int"``) or ``float64`` (``"float"``)."""
    array = np.asarray(values)
    if kind == "int":
        if array.dtype.kind in "iu":
            return array.astype(np.int64, copy=False)
        if array.dtype.kind == "O":  # pandas' nullable ints (Int64) among others
            try:
                array = array.astype(np.float64)
            except (TypeError, ValueError):
                pass
        if array.dtype.kind == "f" and np.all(np.isfinite(array) & (array == np.round(array))):
            return array.astype(np.int64)
        raise ValueError(f"{name}: expected integers, got {array.dtype} values")
    if array.dtype.kind in "iuf":
        return array.astype(np.float64, copy=False)
    try:
        return array.astype(np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected numbers, got {array.dtype} values") from None


def unsupported(name: str, reason: str) -> ValueError:
    """The error of an argument contactmap accepts for compatibility but cannot honour."""
    return ValueError(f"{name}: {reason}")
