"""The dynamics job: quasi-dynamic design, a record's simulated response, harmonic, bifurcation
and IDA studies.

:mod:`.design` (``structure design``), :mod:`.response` (``structure simulate``),
:mod:`.studies` (``structure harmonic | bifurcation | ida``) and :mod:`.stage` (the workflow's
``ida`` stage).
"""
