# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Calling the C kernels of zwidth._core: broadcasting, error policy and scalar results.

Every public function of zwidth goes through :func:`call`.  The kernels return, besides
their outputs, the zw_status of every element; here a failed element either raises
:class:`ZwidthError` naming the parameter (``errors="raise"``, the default) or is masked
(``errors="mask"``): NaN in float outputs, False in boolean ones (so an invalid input is
never reported stable), 0 in integer ones.
"""
from __future__ import annotations

from typing import Any, Callable, Dict, Literal, Mapping, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core

Errors = Literal["raise", "mask"]

STATUS_NAMES: Mapping[int, str] = dict(_core.STATUS_NAMES)
_OK = 0
_DOMAIN = next(code for code, name in STATUS_NAMES.items() if name == "ZW_ERR_DOMAIN")

# What each status says about which parameter is wrong, and how.
_STATUS_PARAMETER = {
    "ZW_ERR_MASS": ("m", "must be > 0"),
    "ZW_ERR_PERIOD": ("T", "must be > 0"),
    "ZW_ERR_DAMPING": ("b", "must be >= 0"),
    "ZW_ERR_DELTA": ("delta", "must be >= 0"),
}


class ZwidthError(ValueError):
    """Invalid input to a zwidth function.

    Attributes: ``status`` (the C core's status name, e.g. ``"ZW_ERR_MASS"``),
    ``parameter`` (the offending argument's name, or None when the fault lies in a
    combination of them, ``ZW_ERR_RANGE``), ``index`` (the element of the broadcast
    inputs, ``()`` for scalars) and ``values`` (every input at that element).
    """

    def __init__(self, message: str, status: str, parameter: Optional[str],
                 index: Tuple[int, ...], values: Mapping[str, float]) -> None:
        super().__init__(message)
        self.status = status
        self.parameter = parameter
        self.index = index
        self.values = dict(values)

    def __reduce__(self) -> Tuple[Any, ...]:
        # picklable (multiprocessing, concurrent.futures): rebuild from every argument
        return (type(self), (str(self), self.status, self.parameter, self.index, self.values))


def _describe(function: str, status: str, names: Sequence[str], values: Sequence[float],
              index: Tuple[int, ...]) -> ZwidthError:
    where = f" at index {index}" if index else ""
    given = dict(zip(names, values))
    parameter: Optional[str] = None
    if status == "ZW_ERR_MASS" and "J" in given:  # a rotary plant
        parameter, rule = "J", "must be > 0"
        what = f"J {rule}, got {given['J']!r}"
    elif status in _STATUS_PARAMETER and _STATUS_PARAMETER[status][0] in given:
        parameter, rule = _STATUS_PARAMETER[status]
        what = f"{parameter} {rule}, got {given[parameter]!r}"
    elif status == "ZW_ERR_NAN":
        parameter = next((n for n, v in given.items() if np.isnan(v)), None)
        what = f"{parameter} is NaN"
    elif status == "ZW_ERR_INF":
        parameter = next((n for n, v in given.items() if np.isinf(v)), None)
        what = f"{parameter} must be finite, got {given.get(parameter or '', float('inf'))!r}"
    elif status == "ZW_ERR_FILTER" and "filter_pole" in given:
        parameter = "filter_pole"
        what = f"filter_pole must be in [0, 1), got {given['filter_pole']!r}"
    elif status == "ZW_ERR_FILTER" and "cutoff" in given:
        parameter = "velocity_filter"
        f_c, T = given["cutoff"], given.get("T", float("nan"))
        what = (f"the low-pass cut-off must be > 0 and below the Nyquist frequency 1/(2T) = "
                f"{0.5 / T:.6g} Hz, got {f_c!r} Hz")
    elif status == "ZW_ERR_ARG" and "radius" in given:
        parameter = "radius"
        what = f"radius must be finite and > 0, got {given['radius']!r}"
    elif status == "ZW_ERR_RANGE":
        inputs = ", ".join(f"{n}={v!r}" for n, v in given.items())
        what = f"a derived quantity (delta = bT/m, T^2/m, K T^2/m, ...) is out of the floating-point range for {inputs}"
    else:
        inputs = ", ".join(f"{n}={v!r}" for n, v in given.items())
        what = f"invalid input ({inputs})"
    return ZwidthError(f"zwidth.{function}: {what}{where} [{status}]", status, parameter, index, given)


class ZwidthTypeError(TypeError):
    """An argument that is not a number or an array of numbers (None, a string, a bool, a
    masked array), named: ``parameter`` is the argument's name."""

    def __init__(self, message: str, parameter: str) -> None:
        super().__init__(message)
        self.parameter = parameter

    def __reduce__(self) -> Tuple[Any, ...]:
        return (type(self), (str(self), self.parameter))


def as_numbers(function: str, name: str, value: Any) -> NDArray[np.float64]:
    """``value`` as a float64 array, refusing what numpy would silently turn into a number
    or into NaN: None, strings ('0.12' included), masked arrays with masked elements (the
    mask would be dropped), objects that are not numbers (ZwidthTypeError naming the
    parameter).  Bools are 0 and 1, as in numpy."""
    if type(value) is float or type(value) is int:  # the common scalar case, fast
        return np.asarray(value, dtype=np.float64)
    if isinstance(value, np.ndarray) and value.dtype == np.float64 and not isinstance(value, np.ma.MaskedArray):
        return value
    what = None
    if value is None:
        what = "None"
    elif isinstance(value, (str, bytes)):
        what = f"a string ({value!r}); convert it with float() if you mean the number"
    elif isinstance(value, np.ma.MaskedArray) and np.ma.getmask(value) is not np.ma.nomask and np.ma.getmask(value).any():
        what = "a masked array with masked elements (fill or drop them first: masks are not carried)"
    if what is None:
        array = np.asarray(np.ma.getdata(value) if isinstance(value, np.ma.MaskedArray) else value)
        if array.dtype.kind in "fiub":  # bools as 0 and 1, as numpy converts them
            return array.astype(np.float64, copy=False)
        if array.dtype.kind in "US":
            what = f"an array of strings (e.g. {array.flat[0]!r})" if array.size else "an array of strings"
        else:
            try:
                return array.astype(np.float64)
            except (TypeError, ValueError):
                what = f"not a number or an array of numbers (a {type(value).__name__}, dtype {array.dtype})"
    raise ZwidthTypeError(f"zwidth.{function}: {name} must be a number or an array of numbers, got {what}", name)


def check_shapes(function: str, names: Sequence[str], arrays: Sequence[NDArray[Any]]) -> None:
    """Raise ValueError naming every parameter and its shape when they do not broadcast
    (numpy's own message lists bare shapes, some of them of internal arguments)."""
    try:
        np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError:
        shapes = ", ".join(f"{n} {a.shape}" for n, a in zip(names, arrays))
        raise ValueError(f"zwidth.{function}: the shapes of {shapes} do not broadcast together") from None


def _as_result(array: NDArray[Any]) -> Any:
    """0-d arrays become numpy scalars, as numpy's ufuncs return them."""
    return array[()] if array.ndim == 0 else array


def call(function: str, kernel: Callable[..., Dict[str, Any]], names: Sequence[str],
         args: Sequence[ArrayLike], errors: Errors = "raise", *,
         domain_is_nan: bool = False, **options: Any) -> Tuple[Dict[str, Any], NDArray[np.int8]]:
    """Run ``kernel`` on ``args`` (named ``names`` in errors) and apply the error policy.

    Returns ``(outputs, status)``: outputs by name (numpy scalars when every input was a
    scalar) and the int8 zw_status array.  ``domain_is_nan`` turns ZW_ERR_DOMAIN ("does
    not exist for this plant") into NaN results instead of an error, whatever ``errors``.
    """
    if errors not in ("raise", "mask"):
        raise ValueError(f"zwidth.{function}: errors must be 'raise' or 'mask', got {errors!r}")
    arrays = [as_numbers(function, name, a) for name, a in zip(names, args)]
    check_shapes(function, names, arrays)
    args = arrays
    result = kernel(*args, **options)
    outputs: Dict[str, NDArray[Any]] = dict(result["outputs"])
    status: NDArray[np.int8] = result["status"]
    if result["errors"]:
        bad = status != _OK
        fatal = bad & (status != _DOMAIN) if domain_is_nan else bad
        if errors == "raise" and fatal.any():
            flat = int(np.flatnonzero(fatal)[0])
            index = tuple(int(i) for i in np.unravel_index(flat, status.shape))
            values = [float(np.broadcast_to(np.asarray(a, dtype=float), status.shape)[index]) for a in args]
            raise _describe(function, STATUS_NAMES[int(status[index])], names, values, index)
        for name, out in outputs.items():
            mask = bad.reshape(bad.shape + (1,) * (out.ndim - bad.ndim))
            fill = np.nan if out.dtype.kind == "f" else 0
            np.copyto(out, np.asarray(fill, dtype=out.dtype), where=np.broadcast_to(mask, out.shape))
    return {name: _as_result(out) for name, out in outputs.items()}, status


def region_code(function: str, region: str) -> int:
    """The C enum value of a region name ('exact', 'legacy', 'passivity', ...)."""
    try:
        return int(_core.REGIONS[region])
    except KeyError:
        known = ", ".join(sorted(_core.REGIONS))
        raise ValueError(f"zwidth.{function}: unknown region {region!r} (one of: {known})") from None
