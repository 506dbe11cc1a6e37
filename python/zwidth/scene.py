# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Scenes: what to simulate, read from TOML files with units (docs/scenes.md).

A scene is one plant (mass m, or inertia J for a rotary device), a controller, the
effects it asks for (a section present is an effect on) and a list of cases that vary
the plant and the gains.  :func:`load_scene` reads a file, a TOML string or a dict,
converts every value to SI units with pint (rad for angles), checks it, and returns a
:class:`Scene` whose cases hold the flat scene dicts that ``zwidth._core.Simulator``
takes.  Every problem raises one :class:`SceneError` naming the file and the key.

    >>> scene = load_scene('''
    ... [plant]
    ... m = "0.1 kg"
    ... b = "30 N*s/m"
    ... T = "0.01 s"
    ... [controller]
    ... alpha = 7.0
    ... beta = 2.0
    ... [reference]
    ... to = "1 m"
    ... ''')
    >>> scene.cases[0].params["K"]
    7000.0
"""
from __future__ import annotations

import dataclasses
import difflib
import math
import sys
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from . import _core
from ._kernels import ZwidthError
from .device import Device

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python < 3.11
    import tomli as tomllib

__all__ = ["SceneError", "Scene", "Case", "load_scene", "parse_quantity", "EFFECTS", "MAX_SUBSTEPS", "MAX_DELAY",
           "SUBSTEP_ACCURACY", "MIN_SUBSTEPS", "DEFAULT_DURATION", "DEFAULT_WINDOWS",
           "DEFAULT_RELATIVE_TOLERANCE", "MAX_SAMPLES", "MAX_KNOB_COUNT", "DEFAULT_LIMIT_CYCLE"]

#: Effects that keep the loop linear and time-invariant, so zwidth.loop decides it exactly.
LINEAR_EFFECTS = ("delay", "velocity_filter", "differentiator", "average")
#: Effect name -> bit of ``zw_sim_scene.effects`` (sim.h).
EFFECTS: Dict[str, int] = dict(_core.SIM_EFFECTS)
#: Effects that need the state between samples (they bring the RK4 integrator).
CONTINUOUS = ("friction", "hand", "actuator")
MAX_SUBSTEPS = 100000        #: ZW_SIM_MAX_SUBSTEPS
MAX_DELAY = 64               #: ZW_SIM_MAX_DELAY
MAX_AVERAGE = 16             #: ZW_SIM_MAX_AVERAGE
#: Default substeps: h * lambda <= this, lambda the fastest rate of the continuous part.
SUBSTEP_ACCURACY = 0.05
MIN_SUBSTEPS = 10            #: ... and never fewer than this many
#: Largest h |s| zw_sim_init accepts (ZW_SIM_RK4_LIMIT in sim.h: RK4's stability limit
#: with a margin), with |s| bounded as in _rk4_rate.
RK4_LIMIT = 2.5
DEFAULT_DURATION = 10.0      #: [s] when [scene] gives none
DEFAULT_WINDOWS = 8          #: verdict windows; the default window is duration / (2 windows)
#: Default verdict tolerance, as a fraction of the position's peak-to-peak over the run.
DEFAULT_RELATIVE_TOLERANCE = 1e-3
#: Most samples a case may have (2**28): at least 5 signals of 8 bytes per sample are
#: recorded, so a case at the limit needs 10 GiB.  Longer runs are refused by the loader.
MAX_SAMPLES = 2 ** 28
#: Signals every run records (t, x, v, x_measured, force): the memory estimate's floor.
_BASIC_SIGNALS = 5
#: reference.at / T must be below this (zw_sim_init: ZW_ERR_RANGE from the sample counts a
#: double no longer holds exactly on).
_STEP_INDEX_LIMIT = 2.0 ** 53
MAX_KNOB_COUNT = 10 ** 6     #: most detents of a [knob]
#: [quantization] limit_cycle: the largest measured motion over the judged windows, in
#: counts, still called stable (a quantized loop cannot settle finer than one count).
DEFAULT_LIMIT_CYCLE = 1

Source = Union[str, Path, Mapping[str, Any]]


class SceneError(ValueError):
    """An invalid scene: one problem, naming where it is.

    Attributes: ``source`` (the file name, or "<string>" / "<dict>"), ``key`` (dotted path
    of the offending key, e.g. "plant.m" or "case[3].alpha"; None for the whole file) and
    ``problem`` (the message without the location).
    """

    def __init__(self, source: str, key: Optional[str], problem: str) -> None:
        where = f"{source}: {key}: " if key else f"{source}: "
        super().__init__(where + problem)
        self.source = source
        self.key = key
        self.problem = problem

    def __reduce__(self) -> Tuple[Any, ...]:
        return (SceneError, (self.source, self.key, self.problem))


# ---------------------------------------------------------------------------------------
# Units
# ---------------------------------------------------------------------------------------

# Kind of quantity -> (translational unit, rotary unit).  Values are stored in these.
UNITS: Dict[str, Tuple[str, str]] = {
    "time": ("s", "s"),
    "frequency": ("Hz", "Hz"),
    "mass": ("kg", "kg*m^2"),
    "damping": ("N*s/m", "N*m*s/rad"),
    "stiffness": ("N/m", "N*m/rad"),
    "position": ("m", "rad"),
    "velocity": ("m/s", "rad/s"),
    "force": ("N", "N*m"),
    "per_position": ("1/m", "1/rad"),
}
_KIND_WORDS = {
    "time": "a time", "frequency": "a frequency", "mass": "a mass", "damping": "a damping",
    "stiffness": "a stiffness", "position": "a position", "velocity": "a velocity",
    "force": "a force", "per_position": "counts per unit of position",
}
_ROTARY_WORDS = {"mass": "an inertia", "position": "an angle", "velocity": "an angular velocity",
                 "force": "a torque", "stiffness": "a rotary stiffness", "damping": "a rotary damping",
                 "per_position": "counts per angle"}

_registry: Any = None


def _ureg() -> Any:
    """The pint registry, made on first use (importing pint takes a few tenths of a second)."""
    global _registry
    if _registry is None:
        import pint
        _registry = pint.UnitRegistry()
    return _registry


def unit_of(kind: str, rotary: bool) -> str:
    """The SI unit a value of this kind is stored in (rad-based for a rotary plant)."""
    return UNITS[kind][1 if rotary else 0]


# ---------------------------------------------------------------------------------------
# Schema: section -> key -> kind
# ---------------------------------------------------------------------------------------

# A key's kind: a quantity kind of UNITS, or "str", "number" (dimensionless), "int",
# "side" ("upper" | "lower").
_SCHEMA: Dict[str, Dict[str, str]] = {
    "scene": {"name": "str", "description": "str", "duration": "time"},
    "plant": {"m": "mass", "J": "mass", "b": "damping", "T": "time"},
    "controller": {"K": "stiffness", "B": "damping", "alpha": "number", "beta": "number"},
    "reference": {"from": "position", "to": "position", "at": "time"},
    "initial": {"x": "position", "v": "velocity"},
    "quantization": {"resolution": "position", "counts": "per_position", "limit_cycle": "int"},
    "friction": {"coulomb": "force", "stiction": "force"},
    "delay": {"samples": "int"},
    "saturation": {"force_max": "force"},
    "velocity_filter": {"cutoff": "frequency"},
    "differentiator": {"kind": "str"},
    "average": {"samples": "int"},
    "actuator": {"tau": "time"},
    "hand": {"mass": "mass", "stiffness": "stiffness", "damping": "damping", "grasp": "time",
             "release": "time", "from": "position", "to": "position", "speed": "velocity"},
    "wall": {"position": "position", "stiffness": "stiffness", "damping": "damping", "side": "side"},
    "knob": {"first": "position", "pitch": "position", "count": "int", "k_detent": "stiffness",
             "k_end": "stiffness", "damping": "damping"},
    "schedule": {"at": "time", "K": "stiffness", "B": "damping"},
    "integrator": {"substeps": "int", "step": "time"},
    "verdict": {"tolerance": "position", "window": "time", "windows": "int"},
    "case": {"label": "str", "description": "str", "m": "mass", "J": "mass", "b": "damping",
             "T": "time", "K": "stiffness", "B": "damping", "alpha": "number", "beta": "number"},
}
_ARRAYS = ("schedule", "case")   # arrays of tables ([[schedule]], [[case]])
_EFFECT_SECTIONS = ("quantization", "friction", "delay", "saturation", "velocity_filter", "hand",
                    "wall", "knob", "schedule", "differentiator", "average", "actuator")


def _example(kind: str, rotary: bool) -> str:
    return {"time": "0.01 s", "frequency": "20 Hz", "mass": "0.1 kg" if not rotary else "85.78e-7 kg*m^2",
            "damping": "30 N*s/m" if not rotary else "2.197e-3 N*m*s/rad",
            "stiffness": "1000 N/m" if not rotary else "0.4 N*m/rad",
            "position": "0.01 m" if not rotary else "0.5 rad",
            "velocity": "0.1 m/s" if not rotary else "1 rad/s",
            "force": "2 N" if not rotary else "0.01 N*m",
            "per_position": "1e5 / m" if not rotary else "4096 / turn"}[kind]


class _Reader:
    """Reads and checks one document; every error names self.source and the key."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.rotary = False

    def fail(self, key: Optional[str], problem: str) -> SceneError:
        return SceneError(self.source, key, problem)

    def table(self, doc: Mapping[str, Any], name: str) -> Optional[Mapping[str, Any]]:
        value = doc.get(name)
        if value is None:
            return None
        if not isinstance(value, Mapping):
            raise self.fail(name, f"must be a table: write it as [{name}], not [[{name}]] or a value")
        self.check_keys(value, name, _SCHEMA[name])
        return value

    def array(self, doc: Mapping[str, Any], name: str) -> List[Mapping[str, Any]]:
        value = doc.get(name)
        if value is None:
            return []
        if isinstance(value, Mapping) or not isinstance(value, (list, tuple)) or \
                not all(isinstance(v, Mapping) for v in value):
            raise self.fail(name, f"must be an array of tables: write each entry as [[{name}]]")
        for i, entry in enumerate(value):
            self.check_keys(entry, f"{name}[{i + 1}]", _SCHEMA[name])
        return list(value)

    def check_keys(self, table: Mapping[str, Any], where: str, known: Mapping[str, str]) -> None:
        for key in table:
            if key not in known:
                close = difflib.get_close_matches(str(key), list(known), n=1)
                hint = f" (did you mean '{close[0]}'?)" if close else ""
                section = where.split("[")[0]
                title = f"[[{section}]]" if section in _ARRAYS else f"[{section}]"
                raise self.fail(f"{where}.{key}", f"unknown key{hint}; {title} takes {', '.join(known)}")

    # -- values ------------------------------------------------------------------------

    def value(self, table: Mapping[str, Any], where: str, key: str, kind: str,
              default: Any = None) -> Any:
        """The value of key in SI units (float), or default when absent."""
        if key not in table:
            return default
        raw = table[key]
        path = f"{where}.{key}"
        if kind == "str":
            if not isinstance(raw, str):
                raise self.fail(path, f"must be a string, got {_show(raw)}")
            return raw
        if kind == "side":
            if raw not in ("upper", "lower"):
                raise self.fail(path, f"must be \"upper\" (the wall occupies x > position) or "
                                      f"\"lower\" (x < position), got {_show(raw)}")
            return raw
        if kind == "int":
            if isinstance(raw, bool) or not isinstance(raw, int):
                raise self.fail(path, f"must be a whole number, got {_show(raw)}")
            return int(raw)
        if kind == "number":
            if isinstance(raw, bool) or not isinstance(raw, (int, float)):
                raise self.fail(path, f"is dimensionless: write a plain number, got {_show(raw)}")
            x = float(raw)
            if not math.isfinite(x):
                raise self.fail(path, f"must be finite, got {raw}")
            return x
        return self.quantity(raw, path, kind)

    def quantity(self, raw: Any, path: str, kind: str) -> float:
        unit = unit_of(kind, self.rotary)
        example = _example(kind, self.rotary)
        if isinstance(raw, bool) or not isinstance(raw, (str, int, float)):
            raise self.fail(path, f"must be a string with units, e.g. \"{example}\", got {_show(raw)}")
        if not isinstance(raw, str):
            raise self.fail(path, f"missing units: write a string with units, e.g. "
                                  f"\"{raw} {unit}\" ({_word(kind, self.rotary)})")
        ureg = _ureg()
        try:
            q = ureg.Quantity(raw)
        except Exception as exc:  # pint raises many kinds for malformed text
            why = str(exc).strip()
            why = f" ({why})" if why else ": not a number followed by units"
            raise self.fail(path, f"cannot read {raw!r} as a number with units{why}; "
                                  f"write e.g. \"{example}\"") from None
        if isinstance(q, ureg.Quantity) and q.unitless and not _is_number(raw):
            # a unit that cancels to a plain number ("10 percent", "5 ppm")
            raise self.fail(path, f"wrong dimension: {raw!r} is a plain number, not {_word(kind, self.rotary)} "
                                  f"(expected units like {unit}, e.g. \"{example}\")")
        if not isinstance(q, ureg.Quantity) or q.unitless:
            number = raw.strip() if _is_number(raw) else example.split()[0]
            raise self.fail(path, f"missing units in {raw!r}: write e.g. \"{number} {unit}\" "
                                  f"({_word(kind, self.rotary)})")
        target = ureg.parse_units(unit)
        if q.dimensionality != target.dimensionality:
            raise self.fail(path, f"wrong dimension: {raw!r} is not {_word(kind, self.rotary)} "
                                  f"(expected units like {unit}, e.g. \"{example}\")")
        try:
            x = float(q.to(target).magnitude)
        except Exception as exc:  # offset units and the like
            raise self.fail(path, f"cannot convert {raw!r} to {unit}: {exc}") from None
        if math.isnan(x):
            raise self.fail(path, f"is NaN: {raw!r}")
        self.check_angle(q, raw, path, kind, x)
        return x

    def check_angle(self, q: Any, raw: str, path: str, kind: str, x: float) -> None:
        """pint takes the radian for a plain number (rad/s and Hz are both 1/s): refuse the
        units where that would silently mis-convert by 2 pi."""
        if not (kind == "frequency" or (kind == "velocity" and self.rotary)):
            return
        try:
            angle = dict(q.to_root_units().unit_items()).get("radian", 0)
        except Exception:  # pragma: no cover - the conversion above succeeded
            angle = 0
        if kind == "frequency" and angle != 0:
            hint = (f" ({raw} is {x / (2 * math.pi):.6g} Hz)" if angle == 1 and _finite(x) else "")
            raise self.fail(path, f"{raw!r} has an angle in its units: give a frequency in Hz (cycles "
                                  f"per second), e.g. \"20 Hz\"{hint}; pint reads rad as a plain "
                                  f"number, so rad/s, deg/s and rpm would count 2 pi times too many "
                                  f"cycles")
        if kind == "velocity" and angle != 1:
            raise self.fail(path, f"{raw!r} is ambiguous for an angular velocity: give an angle per "
                                  f"time, e.g. \"1 rad/s\", \"60 rpm\" or \"90 deg/s\" (10 Hz or 10 / s "
                                  f"could be 10 rad/s or 10 turns per second)")

    def require(self, table: Mapping[str, Any], where: str, key: str, kind: str) -> Any:
        if key not in table:
            section = where.split("[")[0]
            title = f"[[{section}]]" if section in _ARRAYS else f"[{section}]"
            raise self.fail(f"{where}.{key}", f"missing: {title} needs {key}"
                                              + (f" (e.g. {key} = \"{_example(kind, self.rotary)}\")"
                                                 if kind in UNITS else ""))
        return self.value(table, where, key, kind)

    def check(self, ok: bool, path: str, problem: str) -> None:
        if not ok:
            raise self.fail(path, problem)


def parse_quantity(text: str, kind: str, *, rotary: bool = False, what: str = "value") -> float:
    """A string with units (e.g. "20 s", "500 ms") in the SI unit of ``kind`` (a key of
    UNITS); a bare number is taken in that unit.  ValueError (a SceneError) if invalid."""
    r = _Reader("<argument>")
    r.rotary = rotary
    try:
        return float(text)
    except ValueError:
        pass
    return r.quantity(text, what, kind)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _word(kind: str, rotary: bool) -> str:
    return (_ROTARY_WORDS.get(kind) if rotary else None) or _KIND_WORDS[kind]


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _finite(x: float) -> bool:
    return math.isfinite(x)


def _plant_out_of_range(m: float, b: float, T: float, mass_key: str, rotary: bool,
                        exc: ZwidthError) -> Tuple[Tuple[str, ...], str]:
    """The keys and the words for a plant zw_device_init refuses although each of m, b, T
    is valid on its own: a value or a ratio outside the normal doubles."""
    tiny, huge = sys.float_info.min, sys.float_info.max
    mu, bu = unit_of("mass", rotary), unit_of("damping", rotary)
    given = f"{mass_key} = {m:g} {mu}, b = {b:g} {bu}, T = {T:g} s"
    M = mass_key
    candidates: List[Tuple[Tuple[str, ...], str, float]] = [
        ((M,), M, m), (("T",), "T", T)]
    if b > 0:
        candidates.append((("b",), "b", b))
    candidates += [((M, "T"), f"{M}/T", m / T), ((M, "T"), f"{M}/T^2", m / T / T),
                   ((M, "T"), f"T/{M}", T / m)]
    if b > 0:
        candidates.append(((M, "b", "T"), f"delta = b T/{M}", b * (T / m)))
    for keys, name, value in candidates:
        if not tiny <= value <= huge:
            what = "overflows" if value > huge else ("is too small" if value > 0 else "underflows to 0")
            if len(keys) == 1:
                unit = {M: mu, "T": "s", "b": bu}[name]
                return keys, (f"{name} = {value:g} {unit} {what}: zwidth computes in double precision "
                              f"and needs {name} between {tiny:.4g} and {huge:.4g} {unit} (a normal "
                              f"double)")
            return keys, (f"the plant is outside the range zwidth computes in: {name} = {value:g} {what} "
                          f"(it must be a normal double, {tiny:.4g} to {huge:.4g}); {given}: "
                          f"change {', '.join(keys[:-1])} or {keys[-1]}")
    return (M, "b", "T"), f"the plant is outside the range zwidth computes in ({given}): {exc}"


# ---------------------------------------------------------------------------------------
# Scene and Case
# ---------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True, eq=False)
class Case:
    """One simulation of a scene.

    label:     the case's name ([[case]] label, or the scene's name without cases)
    params:    the flat scene dict for ``zwidth._core.Simulator`` (SI units, rad for
               angles): m, b, T, K, B, ..., effects (bits), substeps, schedule
    samples:   number of samples simulated (covers the scene's duration)
    window, windows, tolerance:  the verdict's settings in samples and position units;
               tolerance None: DEFAULT_RELATIVE_TOLERANCE of the position's peak-to-peak
    normalized:  (delta, alpha, beta) of the plant and gains (None for knob/schedule gains)
    description: the case's description, or ""
    limit_cycle: with [quantization], the most counts of measured motion over the judged
               windows the verdict calls stable (a limit cycle); None without it
    """

    label: str
    params: Dict[str, Any] = dataclasses.field(repr=False)
    samples: int
    window: int
    windows: int
    tolerance: Optional[float]
    normalized: Optional[Tuple[float, float, float]] = None
    description: str = ""
    limit_cycle: Optional[int] = None

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Case):
            return NotImplemented
        mine, theirs = dataclasses.astuple(self), dataclasses.astuple(other)
        if mine[:1] + mine[2:] != theirs[:1] + theirs[2:] or self.params.keys() != other.params.keys():
            return False
        return all(np.array_equal(v, other.params[k]) for k, v in self.params.items())

    def __hash__(self) -> int:
        return hash((self.label, self.samples, self.T))

    @property
    def T(self) -> float:
        """Sampling period [s]."""
        return float(self.params["T"])

    @property
    def duration(self) -> float:
        """Simulated time [s] (samples * T)."""
        return self.samples * self.T


@dataclasses.dataclass(frozen=True)
class Scene:
    """A loaded, checked scene (see docs/scenes.md for the file format).

    name, description: from [scene] (name defaults to the file's stem)
    source:    file name, "<string>" or "<dict>"
    duration:  simulated time per case [s]
    rotary:    True for a J plant: positions in rad, forces in N m, gains in N m/rad ...
    effects:   names of the effects on (sections present), in sim.h's order
    cases:     the cases to simulate ([[case]] entries, or one case)
    document:  the scene as a dict of sections, numbers in SI units (rad, N m for a rotary
               plant); :meth:`to_toml` writes it with units and ``load_scene`` of that
               text gives the same scene back
    """

    name: str
    description: str
    source: str = dataclasses.field(compare=False)
    duration: float
    rotary: bool
    effects: Tuple[str, ...]
    cases: Tuple[Case, ...]
    document: Dict[str, Any] = dataclasses.field(repr=False)

    def __repr__(self) -> str:
        labels = ", ".join(c.label for c in self.cases[:6]) + (", ..." if len(self.cases) > 6 else "")
        kind = "rotary" if self.rotary else "translational"
        fx = ", ".join(self.effects) if self.effects else "none (linear)"
        return (f"Scene({self.name!r}, {kind}, duration={self.duration:g} s, effects: {fx}; "
                f"{len(self.cases)} case{'s' if len(self.cases) != 1 else ''}: {labels})")

    @property
    def linear(self) -> bool:
        """Every effect is linear (a delay, a velocity low-pass, or none): zwidth's analysis
        covers the loop simulated (:mod:`zwidth.loop`), so each case gets its analytic
        verdict."""
        return all(e in LINEAR_EFFECTS for e in self.effects)

    @property
    def ideal(self) -> bool:
        """No effect: the paper's ideal sampled loop."""
        return not self.effects

    @property
    def units(self) -> Dict[str, str]:
        """Units of the signals: position, velocity, force, stiffness, damping, time."""
        return {kind: unit_of(kind, self.rotary)
                for kind in ("position", "velocity", "force", "stiffness", "damping", "mass", "time")}

    @property
    def labels(self) -> Tuple[str, ...]:
        return tuple(c.label for c in self.cases)

    def case(self, label: str) -> Case:
        """The case with this label (KeyError if none)."""
        for c in self.cases:
            if c.label == label:
                return c
        raise KeyError(f"scene {self.name!r} has no case {label!r} (cases: {', '.join(self.labels)})")

    def with_duration(self, seconds: float) -> "Scene":
        """The same scene simulated for another duration [s] (the verdict's default
        window follows; an explicit [verdict] window stays)."""
        doc = _deep_copy(self.document)
        doc.setdefault("scene", {})["duration"] = float(seconds)
        return _load_document(doc, self.source, si=True)

    def to_toml(self) -> str:
        """The scene as TOML text in SI units (rad and N m for a rotary plant); loading it
        gives an equal scene."""
        return _to_toml(self.document, self.rotary)


def _deep_copy(doc: Mapping[str, Any]) -> Dict[str, Any]:
    out: Dict[str, Any] = {}
    for k, v in doc.items():
        if isinstance(v, Mapping):
            out[k] = dict(v)
        elif isinstance(v, list):
            out[k] = [dict(e) for e in v]
        else:
            out[k] = v
    return out


# ---------------------------------------------------------------------------------------
# Loading
# ---------------------------------------------------------------------------------------


def load_scene(source: Source, *, name: Optional[str] = None) -> Scene:
    """Read a scene from a TOML file (a path), TOML text (a str containing a newline or
    '='), or a dict of sections as tomllib would give.

    Dimensional values are strings with units ("0.1 kg", "23 N*s/m", "0.4 N*m/rad"; any
    unit pint knows, converted to SI and rad); dimensionless ones (alpha, beta, counts of
    samples) are plain numbers.  Raises :class:`SceneError` (a ValueError) naming the file
    and the key of the first problem found.  ``name`` labels a string or dict source in
    error messages.
    """
    if isinstance(source, Mapping):
        return _load_document(source, name or "<dict>")
    if isinstance(source, Path) or (isinstance(source, str) and "\n" not in source and "=" not in source):
        path = Path(source)
        label = str(path)
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise SceneError(label, None, f"cannot read the scene file: {exc.strerror or exc}") from None
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise SceneError(label, None, f"not UTF-8 text ({exc.reason} at byte {exc.start})") from None
        doc = _parse_toml(text, label)
        return _load_document(doc, label, default_name=path.stem)
    label = name or "<string>"
    return _load_document(_parse_toml(source, label), label)


def _parse_toml(text: str, label: str) -> Dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(label, None, f"invalid TOML: {exc}") from None


def _load_document(doc: Mapping[str, Any], source: str, *, si: bool = False,
                   default_name: Optional[str] = None) -> Scene:
    """Check the document and build the scene.  si=True: the document is a
    Scene.document (numbers already in SI units and rad, no unit strings)."""
    r = _Reader(source)
    if si:
        return _SIBuilder(r, doc, default_name).build()
    return _Builder(r, doc, default_name).build()


class _Builder:
    """Turns a document with unit strings into a Scene."""

    def __init__(self, r: _Reader, doc: Mapping[str, Any], default_name: Optional[str]) -> None:
        self.r = r
        self.doc = doc
        self.default_name = default_name
        self.si: Dict[str, Any] = {}   # the document in SI units (Scene.document)
        self.limit_cycle: Optional[int] = None   # [quantization] limit_cycle, when quantized

    # Values: read through the reader (units), or taken as SI numbers (_SIBuilder).
    def get(self, table: Mapping[str, Any], where: str, key: str, kind: str, default: Any = None) -> Any:
        return self.r.value(table, where, key, kind, default)

    def need(self, table: Mapping[str, Any], where: str, key: str, kind: str) -> Any:
        return self.r.require(table, where, key, kind)

    def build(self) -> Scene:
        r, doc = self.r, self.doc
        for section in doc:
            if section not in _SCHEMA and not isinstance(doc[section], (Mapping, list)):
                raise r.fail(str(section), "a value outside any section: put it in one (e.g. [scene] "
                                           "name, description, duration)")
            if section not in _SCHEMA:
                close = difflib.get_close_matches(str(section), list(_SCHEMA), n=1)
                hint = f" (did you mean [{close[0]}]?)" if close else ""
                raise r.fail(f"[{section}]", f"unknown section{hint}; sections: "
                                             f"{', '.join(_SCHEMA)}")
        tables = {name: (r.array(doc, name) if name in _ARRAYS else r.table(doc, name)) for name in _SCHEMA}

        plant = tables["plant"]
        if plant is None:
            raise r.fail("[plant]", "missing: a scene needs [plant] with m (or J), b and T")
        assert isinstance(plant, Mapping)
        if "m" in plant and "J" in plant:
            raise r.fail("plant.J", "give m (a translational plant, kg) or J (a rotary one, kg*m^2), not both")
        if "m" not in plant and "J" not in plant:
            raise r.fail("plant.m", "missing: [plant] needs m (mass, e.g. \"0.1 kg\") or J (inertia, "
                                    "e.g. \"85.78e-7 kg*m^2\")")
        r.rotary = "J" in plant
        mass_key = "J" if r.rotary else "m"
        si: Dict[str, Any] = {}

        # [scene]
        sc = tables["scene"] or {}
        assert isinstance(sc, Mapping)
        name = self.get(sc, "scene", "name", "str", self.default_name or "scene")
        description = self.get(sc, "scene", "description", "str", "")
        duration = self.get(sc, "scene", "duration", "time", DEFAULT_DURATION)
        r.check(_finite(duration) and duration > 0, "scene.duration", f"must be > 0 s and finite, got {duration:g} s")
        si["scene"] = {"name": name, "description": description, "duration": duration}

        # [plant]
        m = self.need(plant, "plant", mass_key, "mass")
        b = self.need(plant, "plant", "b", "damping")
        T = self.need(plant, "plant", "T", "time")
        self.check_plant(m, b, T, "plant", mass_key)
        si["plant"] = {mass_key: m, "b": b, "T": T}

        # Effects: the sections present.
        effects = tuple(e for e in _EFFECT_SECTIONS if tables[e] not in (None, []))
        if "knob" in effects and "schedule" in effects:
            raise r.fail("[[schedule]]", "a scene has the knob or a schedule, not both: each sets the gains")
        gains_elsewhere = "knob" if "knob" in effects else ("schedule" if "schedule" in effects else None)

        # [controller]
        ctrl = tables["controller"]
        if gains_elsewhere is not None:
            if ctrl is not None:
                where = "[knob]" if gains_elsewhere == "knob" else "[[schedule]]"
                raise r.fail("[controller]", f"remove it: {where} sets the gains of this scene")
            controller: Dict[str, float] = {}
        elif ctrl is None:
            if not tables["case"]:
                raise r.fail("[controller]", "missing: give K and B (real units) or alpha and beta "
                                             "(normalized: alpha = K T^2/m, beta = B T/m)")
            controller = {}   # every case gives its gains
        else:
            assert isinstance(ctrl, Mapping)
            controller = {k: self.get(ctrl, "controller", k, _SCHEMA["controller"][k]) for k in ctrl}
            self.check_controller(controller, "controller", needs_complete=True)
            si["controller"] = dict(controller)

        # [reference], [initial]
        ref = tables["reference"] or {}
        assert isinstance(ref, Mapping)
        x_from = self.get(ref, "reference", "from", "position", 0.0)
        x_to = self.get(ref, "reference", "to", "position", x_from)
        t_step = self.get(ref, "reference", "at", "time", 0.0)
        for key, x in (("from", x_from), ("to", x_to)):
            r.check(_finite(x), f"reference.{key}", f"must be finite, got {x}")
        r.check(_finite(t_step) and t_step >= 0, "reference.at", f"must be >= 0 s and finite, got {t_step:g} s")
        if ref:
            si["reference"] = {"from": x_from, "to": x_to, "at": t_step}
        ini = tables["initial"] or {}
        assert isinstance(ini, Mapping)
        x0 = self.get(ini, "initial", "x", "position", 0.0)
        v0 = self.get(ini, "initial", "v", "velocity", 0.0)
        r.check(_finite(x0), "initial.x", f"must be finite, got {x0}")
        r.check(_finite(v0), "initial.v", f"must be finite, got {v0}")
        if ini:
            si["initial"] = {"x": x0, "v": v0}

        base: Dict[str, Any] = {"m": m, "b": b, "T": T, "x_init": x0, "v_init": v0,
                                "x_eq_before": x_from, "x_eq_after": x_to, "t_step": t_step}
        base.update(self.effect_params(tables, effects, x0, si))
        base["effects"] = sum(EFFECTS[e] for e in effects)

        # [integrator]
        integ = tables["integrator"] or {}
        assert isinstance(integ, Mapping)
        substeps = self.get(integ, "integrator", "substeps", "int")
        step = self.get(integ, "integrator", "step", "time")
        continuous = [e for e in effects if e in CONTINUOUS]
        if integ:
            if not continuous:
                raise r.fail("[integrator]", "remove it: only friction and a hand need an integrator; "
                                             "without them every sample is the exact solution")
            if substeps is not None and step is not None:
                raise r.fail("integrator.step", "give substeps or step, not both")
            if substeps is not None:
                r.check(1 <= substeps <= MAX_SUBSTEPS, "integrator.substeps",
                        f"must be in 1..{MAX_SUBSTEPS}, got {substeps}")
            if step is not None:
                r.check(_finite(step) and step > 0, "integrator.step", f"must be > 0 s, got {step:g} s")
            si["integrator"] = {k: v for k, v in (("substeps", substeps), ("step", step)) if v is not None}

        # [verdict]
        ver = tables["verdict"] or {}
        assert isinstance(ver, Mapping)
        tolerance = self.get(ver, "verdict", "tolerance", "position")
        window_s = self.get(ver, "verdict", "window", "time")
        windows = self.get(ver, "verdict", "windows", "int", DEFAULT_WINDOWS)
        if tolerance is not None:
            r.check(_finite(tolerance) and tolerance >= 0, "verdict.tolerance",
                    f"must be >= 0 and finite, got {tolerance:g}")
        if window_s is not None:
            r.check(_finite(window_s) and window_s > 0, "verdict.window", f"must be > 0 s, got {window_s:g} s")
        r.check(windows >= 2, "verdict.windows", f"must be >= 2 (the verdict compares the first "
                                                 f"and the last window), got {windows}")
        if ver:
            si["verdict"] = {k: v for k, v in (("tolerance", tolerance), ("window", window_s),
                                               ("windows", windows)) if v is not None}

        # [[case]]
        entries = tables["case"]
        assert isinstance(entries, list)
        case_docs: List[Tuple[str, str, Dict[str, Any], str]] = []
        if not entries:
            case_docs.append((name, "", {}, "plant"))
        seen: Dict[str, int] = {}
        si_cases: List[Dict[str, Any]] = []
        for i, entry in enumerate(entries):
            where = f"case[{i + 1}]"
            if "label" not in entry:
                raise r.fail(f"{where}.label", "missing: every [[case]] needs a label")
            label = self.get(entry, where, "label", "str")
            r.check(label.strip() != "", f"{where}.label", "must not be empty")
            if label in seen:
                raise r.fail(f"{where}.label", f"duplicate label {label!r} (also case[{seen[label]}])")
            seen[label] = i + 1
            other_mass = "m" if r.rotary else "J"
            if other_mass in entry:
                kind = "rotary (J)" if r.rotary else "translational (m)"
                raise r.fail(f"{where}.{other_mass}", f"the plant is {kind}: override {mass_key}, not {other_mass}")
            over: Dict[str, Any] = {}
            for key in entry:
                if key in ("label", "description"):
                    continue
                if key in ("K", "B", "alpha", "beta") and gains_elsewhere is not None:
                    raise r.fail(f"{where}.{key}", f"the {gains_elsewhere} sets the gains of this scene: "
                                                   f"a case cannot override {key}")
                over[key] = self.get(entry, where, key, _SCHEMA["case"][key])
            desc = self.get(entry, where, "description", "str", "")
            case_docs.append((label, desc, over, where))
            si_cases.append({"label": label, **({"description": desc} if desc else {}), **over})
        if si_cases:
            si["case"] = si_cases

        cases = tuple(self.make_case(label, desc, over, where, base, controller, mass_key,
                                     duration, substeps, step, tolerance, window_s, windows,
                                     gains_elsewhere)
                      for label, desc, over, where in case_docs)
        return Scene(name=name, description=description, source=r.source, duration=duration,
                     rotary=r.rotary, effects=effects, cases=cases, document=si)

    # -- pieces ------------------------------------------------------------------------

    def check_plant(self, m: float, b: float, T: float, where: str, mass_key: str) -> None:
        r = self.r
        word = "J" if r.rotary else "m"
        r.check(_finite(m) and m > 0, f"{where}.{mass_key}", f"{word} must be > 0 and finite, got {m:g}")
        r.check(_finite(b) and b >= 0, f"{where}.b", f"b must be >= 0 and finite, got {b:g}")
        r.check(_finite(T) and T > 0, f"{where}.T", f"T must be > 0 and finite, got {T:g}")
        # The C core (zw_device_init, which zw_sim_init calls) computes with m, b, T, m/T,
        # m/T^2, T/m and delta = b T/m and needs each a normal double: check it here, so
        # that the simulator never answers a bare [ZW_ERR_RANGE].
        try:
            Device(m, b, T, rotary=r.rotary)
        except ZwidthError as exc:
            keys, problem = _plant_out_of_range(m, b, T, mass_key, r.rotary, exc)
            key = f"{where}.{keys[0]}" if len(keys) == 1 else ("[plant]" if where == "plant" else where)
            raise r.fail(key, problem) from None

    def check_controller(self, c: Mapping[str, float], where: str, *, needs_complete: bool) -> None:
        r = self.r
        real = [k for k in ("K", "B") if k in c]
        norm = [k for k in ("alpha", "beta") if k in c]
        if real and norm:
            raise r.fail(f"{where}.{norm[0]}", f"give K and B (real units) or alpha and beta "
                                               f"(normalized), not both ({', '.join(real + norm)} given)")
        if needs_complete:
            if not real and not norm:
                raise r.fail(f"{where}.K", "missing: give K and B (real units) or alpha and beta "
                                           "(normalized: alpha = K T^2/m, beta = B T/m)")
            pair = ("K", "B") if real else ("alpha", "beta")
            for k in pair:
                if k not in c:
                    raise r.fail(f"{where}.{k}", f"missing: give {pair[0]} and {pair[1]} together")
        for k, v in c.items():
            r.check(_finite(v), f"{where}.{k}", f"must be finite, got {v}")

    def effect_params(self, t: Mapping[str, Any], effects: Sequence[str], x0: float,
                      si: Dict[str, Any]) -> Dict[str, Any]:
        r = self.r
        p: Dict[str, Any] = {}
        if "quantization" in effects:
            q = t["quantization"]
            has_res, has_counts = "resolution" in q, "counts" in q
            if has_res and has_counts:
                raise r.fail("quantization.counts", "give resolution or counts, not both")
            if not has_res and not has_counts:
                raise r.fail("[quantization]", "missing: give resolution (one count, e.g. "
                                               f"\"{_example('position', r.rotary)}\") or counts (counts "
                                               f"per unit, e.g. \"{_example('per_position', r.rotary)}\")")
            if has_res:
                res = self.get(q, "quantization", "resolution", "position")
                r.check(_finite(res) and res > 0, "quantization.resolution", f"must be > 0, got {res:g}")
                r.check(_finite(1.0 / res), "quantization.resolution",
                        f"is too small: {res:g} {unit_of('position', r.rotary)} gives 1/resolution = inf "
                        f"counts per {unit_of('position', r.rotary)} (it must be finite)")
                p["counts_per_unit"] = 1.0 / res
                si["quantization"] = {"resolution": res}
            else:
                counts = self.get(q, "quantization", "counts", "per_position")
                r.check(_finite(counts) and counts > 0, "quantization.counts", f"must be > 0, got {counts:g}")
                p["counts_per_unit"] = counts
                si["quantization"] = {"counts": counts}
            lc = self.get(q, "quantization", "limit_cycle", "int", DEFAULT_LIMIT_CYCLE)
            r.check(lc >= 0, "quantization.limit_cycle", f"must be >= 0 counts, got {lc}")
            self.limit_cycle = lc
            if "limit_cycle" in q:
                si["quantization"]["limit_cycle"] = lc
        if "friction" in effects:
            f = t["friction"]
            coulomb = self.get(f, "friction", "coulomb", "force", 0.0)
            stiction = self.get(f, "friction", "stiction", "force", coulomb)
            r.check(_finite(coulomb) and coulomb >= 0, "friction.coulomb", f"must be >= 0, got {coulomb:g}")
            r.check(_finite(stiction) and stiction >= coulomb, "friction.stiction",
                    f"must be >= coulomb ({coulomb:g}): breaking away takes at least the sliding force, "
                    f"got {stiction:g}")
            r.check(stiction > 0, "friction.coulomb", "give coulomb and/or stiction > 0 (both are 0)")
            p.update(coulomb=coulomb, stiction=stiction)
            si["friction"] = {"coulomb": coulomb, "stiction": stiction}
        if "delay" in effects:
            n = self.need(t["delay"], "delay", "samples", "int")
            r.check(1 <= n <= MAX_DELAY, "delay.samples", f"must be in 1..{MAX_DELAY}, got {n}")
            p["delay_samples"] = n
            si["delay"] = {"samples": n}
        if "saturation" in effects:
            fmax = self.need(t["saturation"], "saturation", "force_max", "force")
            r.check(_finite(fmax) and fmax > 0, "saturation.force_max", f"must be > 0 and finite, got {fmax:g}")
            p["force_max"] = fmax
            si["saturation"] = {"force_max": fmax}
        if "velocity_filter" in effects:
            fc = self.need(t["velocity_filter"], "velocity_filter", "cutoff", "frequency")
            r.check(_finite(fc) and fc > 0, "velocity_filter.cutoff", f"must be > 0 Hz and finite, got {fc:g}")
            p["cutoff_hz"] = fc
            si["velocity_filter"] = {"cutoff": fc}
        if "differentiator" in effects:
            kind = self.need(t["differentiator"], "differentiator", "kind", "str")
            r.check(kind == "tustin", "differentiator.kind",
                    f"must be \"tustin\" (the backward difference is the default: leave the section out), "
                    f"got {kind!r}")
            si["differentiator"] = {"kind": kind}
        if "average" in effects:
            n = self.need(t["average"], "average", "samples", "int")
            r.check(1 <= n <= MAX_AVERAGE, "average.samples", f"must be in 1..{MAX_AVERAGE}, got {n}")
            r.check("velocity_filter" not in effects, "average",
                    "a moving average and a [velocity_filter] low-pass together: the drive's loop has one "
                    "velocity filter (zwidth.loop); keep one of the two sections")
            p["average_samples"] = n
            si["average"] = {"samples": n}
        if "actuator" in effects:
            tau = self.need(t["actuator"], "actuator", "tau", "time")
            r.check(_finite(tau) and tau > 0, "actuator.tau", f"must be > 0 s and finite, got {tau:g}")
            r.check("friction" not in effects, "actuator",
                    "an actuator lag with [friction] is not simulated: stiction's exact break-away needs a "
                    "force constant within the sample (sim.h); drop one of the two sections")
            p["actuator_tau"] = tau
            si["actuator"] = {"tau": tau}
        if "hand" in effects:
            h = t["hand"]
            vals = {"mass": self.get(h, "hand", "mass", "mass", 0.0),
                    "stiffness": self.get(h, "hand", "stiffness", "stiffness", 0.0),
                    "damping": self.get(h, "hand", "damping", "damping", 0.0),
                    "grasp": self.get(h, "hand", "grasp", "time", 0.0),
                    "release": self.get(h, "hand", "release", "time", math.inf),
                    "from": self.get(h, "hand", "from", "position", x0)}
            vals["to"] = self.get(h, "hand", "to", "position", vals["from"])
            vals["speed"] = self.get(h, "hand", "speed", "velocity", math.inf)
            for key in ("mass", "stiffness", "damping"):
                r.check(_finite(vals[key]) and vals[key] >= 0, f"hand.{key}", f"must be >= 0, got {vals[key]:g}")
            r.check(vals["mass"] + vals["stiffness"] + vals["damping"] > 0, "[hand]",
                    "a hand needs mass, stiffness or damping > 0 (all are 0)")
            r.check(_finite(vals["grasp"]) and vals["grasp"] >= 0, "hand.grasp", f"must be >= 0 s, got {vals['grasp']:g}")
            r.check(vals["release"] > vals["grasp"], "hand.release",
                    f"must come after grasp ({vals['grasp']:g} s), got {vals['release']:g} s")
            for key in ("from", "to"):
                r.check(_finite(vals[key]), f"hand.{key}", f"must be finite, got {vals[key]}")
            r.check(vals["speed"] > 0, "hand.speed", f"must be > 0, got {vals['speed']:g}")
            p.update(hand_mass=vals["mass"], hand_stiffness=vals["stiffness"], hand_damping=vals["damping"],
                     hand_t_grasp=vals["grasp"], hand_t_release=vals["release"], hand_from=vals["from"],
                     hand_to=vals["to"], hand_speed=vals["speed"])
            si["hand"] = {k: v for k, v in vals.items() if not (k in ("release", "speed") and v == math.inf)}
        if "wall" in effects:
            w = t["wall"]
            pos = self.need(w, "wall", "position", "position")
            k = self.need(w, "wall", "stiffness", "stiffness")
            d = self.get(w, "wall", "damping", "damping", 0.0)
            side = self.get(w, "wall", "side", "side", "upper")
            r.check(_finite(pos), "wall.position", f"must be finite, got {pos}")
            r.check(_finite(k) and k > 0, "wall.stiffness", f"must be > 0 and finite, got {k:g}")
            r.check(_finite(d), "wall.damping", f"must be finite, got {d}")
            p.update(wall_position=pos, wall_stiffness=k, wall_damping=d, wall_side=1 if side == "upper" else -1)
            si["wall"] = {"position": pos, "stiffness": k, "damping": d, "side": side}
        if "knob" in effects:
            kb = t["knob"]
            first = self.get(kb, "knob", "first", "position", 0.0)
            pitch = self.need(kb, "knob", "pitch", "position")
            count = self.need(kb, "knob", "count", "int")
            k_detent = self.need(kb, "knob", "k_detent", "stiffness")
            k_end = self.need(kb, "knob", "k_end", "stiffness")
            damping = self.get(kb, "knob", "damping", "damping", 0.0)
            r.check(_finite(first), "knob.first", f"must be finite, got {first}")
            r.check(_finite(pitch) and pitch > 0, "knob.pitch", f"must be > 0, got {pitch:g}")
            r.check(count >= 2, "knob.count", f"a knob needs >= 2 positions, got {count}")
            r.check(count <= MAX_KNOB_COUNT, "knob.count",
                    f"at most {MAX_KNOB_COUNT:,} positions, got {count:,}")
            r.check(_finite(k_detent) and k_detent > 0, "knob.k_detent", f"must be > 0, got {k_detent:g}")
            r.check(_finite(k_end) and k_end > 0, "knob.k_end", f"must be > 0, got {k_end:g}")
            r.check(_finite(damping), "knob.damping", f"must be finite, got {damping}")
            last = first + float(count - 1) * pitch     # as zw_sim_init computes it
            r.check(_finite(last), "knob.pitch", f"the last detent, first + (count - 1) pitch = {last:g}, "
                                                 f"must be finite")
            p.update(knob_first=first, knob_pitch=pitch, knob_count=count, knob_k_detent=k_detent,
                     knob_k_end=k_end, knob_damping=damping)
            si["knob"] = {"first": first, "pitch": pitch, "count": count, "k_detent": k_detent,
                          "k_end": k_end, "damping": damping}
        if "schedule" in effects:
            rows: List[Tuple[float, float, float]] = []
            si_rows = []
            for i, seg in enumerate(t["schedule"]):
                where = f"schedule[{i + 1}]"
                at = self.need(seg, where, "at", "time")
                K = self.need(seg, where, "K", "stiffness")
                B = self.need(seg, where, "B", "damping")
                for key, v in (("K", K), ("B", B)):
                    r.check(_finite(v), f"{where}.{key}", f"must be finite, got {v}")
                if i == 0:
                    r.check(at == 0, f"{where}.at", f"the first segment starts at 0 s, got {at:g} s")
                else:
                    r.check(_finite(at) and at > rows[-1][0], f"{where}.at",
                            f"must come after the previous segment ({rows[-1][0]:g} s), got {at:g} s")
                rows.append((at, K, B))
                si_rows.append({"at": at, "K": K, "B": B})
            p["schedule"] = np.array(rows, dtype=np.float64).reshape(-1, 3)
            si["schedule"] = si_rows
        return p

    def make_case(self, label: str, description: str, over: Mapping[str, Any], where: str,
                  base: Mapping[str, Any], controller: Mapping[str, float], mass_key: str,
                  duration: float, substeps: Optional[int], step: Optional[float],
                  tolerance: Optional[float], window_s: Optional[float], windows: int,
                  gains_elsewhere: Optional[str]) -> Case:
        r = self.r
        params = dict(base)
        if "schedule" in params:
            params["schedule"] = np.array(params["schedule"], copy=True)
        m = over.get(mass_key, base["m"])
        b = over.get("b", base["b"])
        T = over.get("T", base["T"])
        self.check_plant(m, b, T, where, mass_key)
        params.update(m=m, b=b, T=T)
        # zw_sim_init counts the step's sample index exactly, and refuses it from 2**53 on.
        t_step = params["t_step"]
        if not t_step / T < _STEP_INDEX_LIMIT:      # also inf
            raise r.fail("reference.at", f"case {label!r}: at / T = {t_step:g} s / {T:g} s = {t_step / T:.4g} "
                                         f"samples, not below 2**53, the sample index the simulator counts "
                                         f"exactly; no run is that long: give a time within the duration, "
                                         f"or leave reference.to out for no step")
        normalized: Optional[Tuple[float, float, float]] = None
        if gains_elsewhere is None:
            ctrl_over = {k: over[k] for k in ("K", "B", "alpha", "beta") if k in over}
            if ctrl_over:
                same_form = all((k in ("K", "B")) == ("K" in controller or "B" in controller) for k in ctrl_over)
                merged = {**controller, **ctrl_over} if same_form else dict(ctrl_over)
                self.check_controller(merged, where, needs_complete=True)
            elif controller:
                merged = dict(controller)
            else:
                raise r.fail(f"{where}.K", "missing: give K and B (or alpha and beta) in this case "
                                           "or in [controller]")
            # The scales of zw_device_init: m/T and (m/T)/T (T ** 2 could overflow or underflow
            # where these are fine; check_plant made them normal numbers).
            b_scale = m / T
            k_scale = b_scale / T
            if "alpha" in merged:
                K, B = merged["alpha"] * k_scale, merged["beta"] * b_scale
                normalized = (b * (T / m), float(merged["alpha"]), float(merged["beta"]))
            else:
                K, B = merged["K"], merged["B"]
                normalized = (b * (T / m), K / k_scale, B / b_scale)
            r.check(_finite(K) and _finite(B), where, f"the gains overflow: K = {K:g}, B = {B:g}")
            params.update(K=K, B=B)
        else:
            params.update(K=0.0, B=0.0)

        # Integrator: substeps for the continuous effects (sim.h: RK4 steps per sample).
        fx = [e for e, bit in EFFECTS.items() if params["effects"] & bit]
        if any(e in CONTINUOUS for e in fx):
            key = "integrator.step" if step is not None and substeps is None else "integrator.substeps"
            if substeps is not None:
                n = substeps
            elif step is not None:
                per_sample = T / step
                if not per_sample < MAX_SUBSTEPS + 0.5:     # also inf (a tiny step)
                    raise r.fail(key, f"case {label!r}: T / step = {T:g} s / {step:g} s = {per_sample:.6g} "
                                      f"substeps per sample, more than {MAX_SUBSTEPS}: lengthen the step")
                n = max(1, int(round(per_sample)))
            else:
                needed = _substeps_needed(params)
                if not needed <= MAX_SUBSTEPS:               # also inf and NaN
                    raise r.fail(_fastest_key(params, where),
                                 f"{needed:.6g} substeps per sample needed (more than "
                                 f"{MAX_SUBSTEPS}): the continuous part is too fast for T = {T:g} s")
                n = max(MIN_SUBSTEPS, int(math.ceil(needed)))
            rate = _rk4_rate(params)
            if not _rk4_stable(rate, T, n):
                need = _rk4_fewest_substeps(rate, T)
                use = (f"use at least {need}" if need <= MAX_SUBSTEPS else
                       f"even {MAX_SUBSTEPS} are too few: lengthen T or slow the continuous part")
                raise r.fail(key if (substeps is not None or step is not None) else _fastest_key(params, where),
                             f"{n} substeps per sample ({T / n:g} s) are too few for "
                             f"{label!r}: RK4 diverges when the step times the fastest rate "
                             f"({rate:g} /s) exceeds {RK4_LIMIT:g}; {use} (or omit "
                             f"[integrator]: the default is accurate)")
            params["substeps"] = n

        # Samples: refuse a run that cannot be held in memory (and duration / T = inf).
        ratio = duration / T * (1.0 - 1e-12)
        if not ratio <= MAX_SAMPLES:
            memory = (f"{ratio * _BASIC_SIGNALS * 8 / 2 ** 30:.3g} GiB" if _finite(ratio)
                      else "more memory than any computer has")
            raise r.fail("scene.duration",
                         f"case {label!r}: duration / T = {duration:g} s / {T:g} s = {ratio:.4g} samples, more "
                         f"than the {MAX_SAMPLES:,} (2**28) a case may have: the run would need {memory} "
                         f"({_BASIC_SIGNALS} signals of 8 bytes per sample at least); shorten the duration "
                         f"or lengthen T")
        samples = max(1, int(math.ceil(ratio)))
        if window_s is not None:
            per_window = window_s / T
            if not per_window <= MAX_SAMPLES:
                raise r.fail("verdict.window", f"case {label!r}: window / T = {window_s:g} s / {T:g} s = "
                                               f"{per_window:.4g} samples, longer than the run ({samples})")
            window = max(1, int(round(per_window)))
        else:
            window = max(1, samples // (2 * windows))
        if window * windows > samples:
            raise r.fail("verdict.window" if window_s is not None else "scene.duration",
                         f"case {label!r}: the verdict needs {windows} windows of {window} samples, but the run "
                         f"has {samples} (T = {T:g} s): lengthen the duration or shorten the window")
        return Case(label=label, params=params, samples=samples, window=window, windows=windows,
                    tolerance=tolerance, normalized=normalized, description=description,
                    limit_cycle=self.limit_cycle)


class _SIBuilder(_Builder):
    """Reads a Scene.document: numbers already in SI units (and rad), no unit strings."""

    def get(self, table: Mapping[str, Any], where: str, key: str, kind: str, default: Any = None) -> Any:
        if key not in table:
            return default
        raw = table[key]
        if kind in UNITS:
            if isinstance(raw, bool) or not isinstance(raw, (int, float)):
                raise self.r.fail(f"{where}.{key}", f"must be a number in {unit_of(kind, self.r.rotary)} "
                                                    f"(a Scene.document), got {_show(raw)}")
            return float(raw)
        return self.r.value(table, where, key, kind, default)

    def need(self, table: Mapping[str, Any], where: str, key: str, kind: str) -> Any:
        if key not in table:
            self.r.require(table, where, key, kind)  # raises
        return self.get(table, where, key, kind)


def _rates(params: Mapping[str, Any]) -> Tuple[float, Optional[Tuple[float, float]]]:
    """The rates of the continuous part: b/m, and with a hand held ((b + b_h)/(m + m_h),
    sqrt(k_h/(m + m_h))) (None without a hand), each evaluated as sim.c does."""
    m, b = float(params["m"]), float(params["b"])
    if not int(params.get("effects", 0)) & EFFECTS["hand"]:
        return b / m, None
    mh = m + float(params.get("hand_mass", 0.0))
    return b / m, ((b + float(params.get("hand_damping", 0.0))) / mh,
                   math.sqrt(float(params.get("hand_stiffness", 0.0)) / mh))


def _lag_rate(params: Mapping[str, Any]) -> float:
    """The actuator lag's rate 1/tau (0 without [actuator]), as sim.c's zw_sim_init."""
    if not int(params.get("effects", 0)) & EFFECTS["actuator"]:
        return 0.0
    return 1.0 / float(params["actuator_tau"])


def _fastest_key(params: Mapping[str, Any], plant_key: str) -> str:
    """The key that makes the continuous part fast: hand.stiffness or hand.damping when the
    held hand's rate is the fastest, else the plant's (plant_key: "plant" or "case[i]")."""
    rate, held = _rates(params)
    if held is None or max(held) <= rate:
        return plant_key
    return "hand.stiffness" if held[1] >= held[0] else "hand.damping"


def _rk4_rate(params: Mapping[str, Any]) -> float:
    """The bound on |s| of the continuous part that zw_sim_init checks (sim.h,
    ZW_SIM_RK4_LIMIT): b/m, and with a hand (b + b_h)/(m + m_h) + sqrt(k_h/(m + m_h)).
    Evaluated exactly as sim.c's fastest_rate(), so that the loader and the C core agree."""
    rate, held = _rates(params)
    if held is not None and held[0] + held[1] > rate:
        rate = held[0] + held[1]
    if _lag_rate(params) > rate:
        rate = _lag_rate(params)
    return rate


def _rk4_stable(rate: float, T: float, n: int) -> bool:
    """zw_sim_init's test, in its order of evaluation: rate * (T / n) <= ZW_SIM_RK4_LIMIT."""
    return rate * (T / float(n)) <= RK4_LIMIT


def _rk4_fewest_substeps(rate: float, T: float) -> int:
    """The fewest substeps that pass :func:`_rk4_stable` (MAX_SUBSTEPS + 1 if none does)."""
    guess = rate * T / RK4_LIMIT
    if not guess <= MAX_SUBSTEPS:
        return MAX_SUBSTEPS + 1
    n = max(1, int(math.ceil(guess)) - 1)
    while n <= MAX_SUBSTEPS and not _rk4_stable(rate, T, n):
        n += 1
    return n


def _substeps_needed(params: Mapping[str, Any]) -> float:
    """T lambda / SUBSTEP_ACCURACY (may be inf): see :func:`default_substeps`."""
    rate, held = _rates(params)
    if held is not None:
        rate = max(rate, *held)
    rate = max(rate, _lag_rate(params))
    return float(params["T"]) * rate / SUBSTEP_ACCURACY


def default_substeps(params: Mapping[str, Any]) -> int:
    """RK4 steps per sample so that h * lambda <= SUBSTEP_ACCURACY (h = T/n), lambda the
    fastest rate of the continuous part: b/m, and with a hand (b + b_h)/(m + m_h) and
    sqrt(k_h/(m + m_h)); at least MIN_SUBSTEPS.  ValueError if that is not finite."""
    needed = _substeps_needed(params)
    if not math.isfinite(needed):
        raise ValueError(f"default_substeps: T lambda / {SUBSTEP_ACCURACY} = {needed} is not finite")
    return max(MIN_SUBSTEPS, int(math.ceil(needed)))


# ---------------------------------------------------------------------------------------
# Writing TOML (Scene.to_toml)
# ---------------------------------------------------------------------------------------


def _toml_value(value: Any, kind: str, rotary: bool) -> str:
    if kind in UNITS:
        return f"\"{float(value)!r} {unit_of(kind, rotary)}\""
    if kind in ("str", "side"):
        return '"' + str(value).replace("\\", "\\\\").replace('"', '\\"') + '"'
    if kind == "int":
        return str(int(value))
    return repr(float(value))


def _to_toml(doc: Mapping[str, Any], rotary: bool) -> str:
    lines: List[str] = []
    for section, schema in _SCHEMA.items():
        if section not in doc:
            continue
        entries = doc[section] if section in _ARRAYS else [doc[section]]
        for entry in entries:
            if not entry:
                continue
            lines.append(f"[[{section}]]" if section in _ARRAYS else f"[{section}]")
            for key, value in entry.items():
                lines.append(f"{key} = {_toml_value(value, schema[key], rotary)}")
            lines.append("")
    return "\n".join(lines)


def signal_units(rotary: bool) -> Dict[str, str]:
    """Unit of every trace signal (zw_sim_trace field names)."""
    pos, vel, force = unit_of("position", rotary), unit_of("velocity", rotary), unit_of("force", rotary)
    return {"t": "s", "x": pos, "v": vel, "x_measured": pos, "force": force, "force_command": force,
            "stiffness": unit_of("stiffness", rotary), "stiffness_planned": unit_of("stiffness", rotary),
            "damping": unit_of("damping", rotary), "velocity_estimate": vel, "wall_force": force,
            "friction": force, "hand_force": force, "hand_target": pos}

