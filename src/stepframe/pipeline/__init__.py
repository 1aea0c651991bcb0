"""Pipeline: workflow files, staged runs with a content-addressed cache (DESIGN.md, The pipeline).

- :mod:`~stepframe.pipeline.workflow`: workflow (scene) files, checked with file:line errors;
- :mod:`~stepframe.pipeline.stages`: the stage registry (inventory, features, site,
  amplification, selection; later stages plug in with ``register_stage``);
- :mod:`~stepframe.pipeline.plan`: only the stages the requested outputs need;
- :mod:`~stepframe.pipeline.store`: per-item results keyed by content, parameters and version;
- :mod:`~stepframe.pipeline.lock`: one run per workspace (an OS lock);
- :mod:`~stepframe.pipeline.runner`: ``stepframe run``;
- :mod:`~stepframe.pipeline.scheduler`: process pool or Dask.

Heavy imports happen inside functions so that ``stepframe --help`` stays fast.
"""
