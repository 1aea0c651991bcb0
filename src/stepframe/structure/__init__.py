"""Structure: stepping-frame models, quasi-dynamic design and the exact simulator.

Modules: :mod:`~stepframe.structure.frame` (PortalFrame, AFrame, eqs. 4.6-4.16),
:mod:`~stepframe.structure.frame_file` (FRAME.toml), :mod:`~stepframe.structure.design_spectrum`
and :mod:`~stepframe.structure.quasi_dynamic` (Part 1 of the paper: fixed points, stability),
:mod:`~stepframe.structure.damping`, :mod:`~stepframe.structure.simulator` (eqs. 4.11-4.12 with
impact; its status and event codes in :mod:`~stepframe.structure.status`),
:mod:`~stepframe.structure.period_amplitude` (the free-vibration law T(A)),
:mod:`~stepframe.structure.aframe_hysteretic` (the A-frame with its hysteretic damping and
sticking), :mod:`~stepframe.structure.rocking_block` (Housner's block beyond small angles),
:mod:`~stepframe.structure.work` (work estimates checked before a run) and
:mod:`~stepframe.structure.plots`. The names below are imported when first used (module
``__getattr__``), so importing this package stays cheap.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from stepframe._lazy import lazy_exports

if TYPE_CHECKING:
    from stepframe.structure.design_spectrum import TabulatedSpectrum, TwoPeriodSpectrum
    from stepframe.structure.frame import AFrame, PortalFrame
    from stepframe.structure.frame_file import frame_template, read_frame_file
    from stepframe.structure.period_amplitude import period_amplitude
    from stepframe.structure.quasi_dynamic import (
        DesignCase,
        DesignResult,
        SteppingMap,
        design_displacement,
        iterate,
        read_case,
    )
    from stepframe.structure.simulator import SimulationResult, simulate

_EXPORTS = {
    "PortalFrame": "stepframe.structure.frame",
    "AFrame": "stepframe.structure.frame",
    "read_frame_file": "stepframe.structure.frame_file",
    "frame_template": "stepframe.structure.frame_file",
    "TwoPeriodSpectrum": "stepframe.structure.design_spectrum",
    "TabulatedSpectrum": "stepframe.structure.design_spectrum",
    "SteppingMap": "stepframe.structure.quasi_dynamic",
    "DesignCase": "stepframe.structure.quasi_dynamic",
    "DesignResult": "stepframe.structure.quasi_dynamic",
    "design_displacement": "stepframe.structure.quasi_dynamic",
    "iterate": "stepframe.structure.quasi_dynamic",
    "read_case": "stepframe.structure.quasi_dynamic",
    "period_amplitude": "stepframe.structure.period_amplitude",
    "simulate": "stepframe.structure.simulator",
    "SimulationResult": "stepframe.structure.simulator",
}


__getattr__ = lazy_exports(__name__, _EXPORTS)


__all__ = [
    "AFrame",
    "DesignCase",
    "DesignResult",
    "PortalFrame",
    "SimulationResult",
    "SteppingMap",
    "TabulatedSpectrum",
    "TwoPeriodSpectrum",
    "design_displacement",
    "frame_template",
    "iterate",
    "period_amplitude",
    "read_case",
    "read_frame_file",
    "simulate",
]
