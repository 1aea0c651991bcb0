"""The workflow engine: workflow files, the plan, the runner, the store, the lock, executors.

It runs whatever stages it is handed (:class:`~stepframe.pipeline.engine.stage.StageTable`;
the shipped ones come from :func:`stepframe.pipeline.stages.shipped_stages`) and imports no
science and no job: ``tests/test_architecture.py`` checks it. Modules: :mod:`.stage` (the stage
types), :mod:`.workflow` (reading and checking a workflow file), :mod:`.plan` (the stages the
outputs need, ordered by their upstreams), :mod:`.runner` (a run: check, lock, compute, store,
publish), :mod:`.store` (results keyed by content), :mod:`.lock` (one run per workspace),
:mod:`.scheduler` (process pool, Dask or any executor), :mod:`.run_options` (the run's options),
:mod:`.shipped` (the workflows shipped with the package, by name), :mod:`.same_content` (inputs
with the same bytes are one item), :mod:`.integrity` (checksums, the index file, quarantine),
:mod:`.history` (a per-item output's table and failures, and what earlier runs saw),
:mod:`.run_log` (one JSON line per run) and :mod:`.upkeep` (``stepframe store verify|compact``).
"""
