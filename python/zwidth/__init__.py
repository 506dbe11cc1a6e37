# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth: the exact stability region of impedance-controlled haptic devices and drives.

A drive renders a virtual stiffness K and damping B on a mass m with physical damping b,
sampled every T.  zwidth says which (K, B) keep it stable for every such plant (Wang et
al., IEEE Access 12, 2024), the largest K and B it can render, and how m, b and T move
those limits.  Every number comes from zwidth's C core; the functions here broadcast over
numpy arrays and run their loops in C.

Normalized space (delta = b T/m, alpha = K T^2/m, beta = B T/m):
    check, verdict, spectral_radius, radius_within, char_poly, coefficients,
    extremes, alpha_max, beta_interval, hyperbola_top, corner, boundary (the outline as arrays)
Real units:
    Device(m, b, T) / Device.rotary(J, b, T) with is_stable, verdict, margin,
    spectral_radius, radius_within, k_max, b_range, boundary, extremes, influence, normalize
Results print and compare by name: Verdict.deciding is a Bound ('line' == Bound.LINE), the
Influence trends are Trends ('rises'); arrays print as a summary (shape, range).
The loop a real drive runs (delay, velocity filter, Tustin differentiator; zwidth.loop):
    check(..., delay=1, filter_pole=a), Device(..., delay=1, velocity_filter=("lowpass", 30.0)),
    LoopVerdict (the deciding boundary: z=1, z=-1 or a complex pair at X Hz), loop_poly
Simulation (time domain, paper Fig. 13; scenes as TOML files, docs/scenes.md):
    load_scene -> Scene, simulate -> SimulationSet of Simulation (numpy arrays, SimVerdict,
    the analytic verdict for linear scenes), SceneError
Also: zwidth.plot (matplotlib, optional extra "plot"), zwidth.modbus (pymodbus client of
a drive, optional extra "modbus"), both imported on first use, the ``zwidth`` command line.
"""
from __future__ import annotations

from typing import Dict as _Dict

from . import _core
from ._kernels import STATUS_NAMES, ZwidthError, ZwidthTypeError
from .box import BoxCertificate, PlantBox
from .device import Device, LoopNotSupported, PlantSensitivity
from .loop import Loop
from .normalized import (alpha_max, beta_interval, boundary, char_poly, check, coefficients,
                         coefficients_literal, corner, extremes, hyperbola_top, loop_boundary, loop_poly,
                         radius_within, spectral_radius, verdict)
from .results import (Bound, Boundary, BoundaryPoint, Coefficients, DeviceBoundary, DeviceExtremes,
                      DeviceLoopExtremes, Extremes, Influence, Interval, LoopBoundary, LoopExtremes, LoopInfluence,
                      LoopVerdict, Normalized, Trend, Verdict)
from .scene import Scene, SceneError, load_scene
from .sim import Simulation, SimulationSet, SimVerdict, simulate

#: The release (csrc/include/zwidth/version.h, as compiled into the core).
__version__: str = _core.VERSION

#: The critical normalized dampings and K_mmax ratios of the paper (from the C headers).
CONSTANTS: _Dict[str, float] = dict(_core.CONSTANTS)
DELTA0: float = CONSTANTS["DELTA0"]        #: the line starts to bite (legacy region wrong above)
DELTA1: float = CONSTANTS["DELTA1"]        #: alpha_mmax moves from the hyperbola's top to the corner
DELTA2: float = CONSTANTS["DELTA2"]        #: beta at alpha_mmax turns negative
DELTA_K1: float = CONSTANTS["DELTA_K1"]    #: local min of alpha_mmax / delta
DELTA_K2: float = CONSTANTS["DELTA_K2"]    #: local max of alpha_mmax / delta
DELTA_B: float = CONSTANTS["DELTA_B"]      #: local min of beta_mmax / delta
DELTA_BB: float = CONSTANTS["DELTA_BB"]    #: local min of beta_mmax
DELTA_KM: float = CONSTANTS["DELTA_KM"]    #: below delta_K1, where alpha_mmax/delta regains its local max
#: Constraint bits of Verdict.deciding / Verdict.violated ('damping', 'stiffness', ...).
BOUNDS: _Dict[str, int] = dict(_core.BOUNDS)
#: Deciding boundaries of a LoopVerdict ('none', 'z=1', 'z=-1', 'complex').
LOOP_BOUNDARIES: _Dict[str, int] = dict(_core.LOOP_BOUNDARIES)
#: Region names accepted by check(..., region=...).
REGIONS = tuple(_core.REGIONS)

__all__ = [
    "__version__", "ZwidthError", "ZwidthTypeError", "Bound", "LoopBoundary", "Trend", "boundary", "Boundary",
    "DeviceBoundary", "STATUS_NAMES", "CONSTANTS", "BOUNDS", "REGIONS",
    "DELTA0", "DELTA1", "DELTA2", "DELTA_K1", "DELTA_K2", "DELTA_B", "DELTA_BB", "DELTA_KM",
    "LOOP_BOUNDARIES", "Loop", "LoopVerdict", "LoopNotSupported", "loop_poly", "loop_boundary",
    "LoopExtremes", "DeviceLoopExtremes", "LoopInfluence",
    "check", "verdict", "spectral_radius", "radius_within", "char_poly", "coefficients",
    "coefficients_literal", "extremes", "hyperbola_top", "corner", "alpha_max", "beta_interval",
    "Device", "PlantBox", "BoxCertificate", "Verdict", "Coefficients", "Extremes", "BoundaryPoint", "Interval", "Normalized",
    "DeviceExtremes", "Influence", "PlantSensitivity",
    "load_scene", "Scene", "SceneError", "simulate", "Simulation", "SimulationSet", "SimVerdict",
]
del annotations  # the __future__ import, not part of the API


def __getattr__(name: str) -> object:
    """zwidth.plot and zwidth.modbus after ``import zwidth`` alone: imported on first use,
    so that neither matplotlib nor pymodbus is needed to import zwidth (PEP 562)."""
    if name in ("plot", "modbus"):
        import importlib
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'zwidth' has no attribute {name!r}")
