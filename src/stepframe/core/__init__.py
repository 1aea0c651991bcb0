"""Core: the few pieces every area shares (no science here).

- :mod:`stepframe.core.io`: :func:`~stepframe.core.io.atomic_write` (the one way to write a
  user-visible file) and :func:`~stepframe.core.io.read_toml` (the one TOML reader, with
  ``file:line`` errors);
- :mod:`stepframe.core.results`: the one status vocabulary and the failure-table layout;
- :mod:`stepframe.core.execution`: :func:`~stepframe.core.execution.map_items`, the one executor
  for batches (process pool, any ``concurrent.futures.Executor``, failures recorded);
- :mod:`stepframe.core.jsonable`: :func:`~stepframe.core.jsonable.to_jsonable`, the one
  conversion of results to JSON values (NaN and ±inf as null).

The areas (records, stochastic, structure) may import :mod:`stepframe.core`; it imports none of
them.
"""
