"""The catalogue job: a folder of records → each component's features and fitted B-P parameters.

:mod:`.fitted` (one record's features, fit and NetCDF; a catalogue's features table),
:mod:`.fitted_files` (what ``stochastic fit`` and ``stochastic features`` write),
:mod:`.fit_options` (how a record is fitted; light), :mod:`.record_spectra` (``records info``
and ``records spectrum``), :mod:`.example_files` (the embedded example as AT2 files) and
:mod:`.stage` (the workflow's ``inventory`` and ``features`` stages).
"""
