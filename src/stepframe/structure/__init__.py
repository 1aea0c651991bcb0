"""Structure: stepping-frame models, quasi-dynamic design and the exact simulator.

Modules: :mod:`~stepframe.structure.frame` (PortalFrame, AFrame, eqs. 4.6-4.16),
:mod:`~stepframe.structure.frame_file` (FRAME.toml), :mod:`~stepframe.structure.design_spectrum`
and :mod:`~stepframe.structure.quasi_dynamic` (Part 1 of the paper: fixed points, stability),
:mod:`~stepframe.structure.damping`, :mod:`~stepframe.structure.simulator` (eqs. 4.11-4.12 with
impact; its status and event codes in :mod:`~stepframe.structure.status`),
:mod:`~stepframe.structure.period_amplitude` (the free-vibration law T(A)).
"""
