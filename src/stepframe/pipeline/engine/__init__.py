"""The workflow engine: workflow files, the plan, the runner, the store, the lock, executors.

It runs whatever stages it is handed (:class:`~stepframe.pipeline.engine.stage.StageTable`;
the shipped ones come from :func:`stepframe.pipeline.stages.shipped_stages`) and imports no
science and no job: ``tests/test_architecture.py`` checks it. Modules: :mod:`.stage` (the stage
types), :mod:`.workflow` (reading and checking a workflow file), :mod:`.plan` (the stages the
outputs need, ordered by their upstreams), :mod:`.runner` (a run: check, lock, compute, store,
publish), :mod:`.store` (results keyed by content), :mod:`.lock` (one run per workspace),
:mod:`.scheduler` (process pool, Dask or any executor), :mod:`.run_options` (the run's options)
and :mod:`.shipped` (the workflows shipped with the package, by name).
"""
