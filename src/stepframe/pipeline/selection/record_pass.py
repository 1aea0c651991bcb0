"""The selection's one pass over its candidates' records, in the workers: samples read where they
are used, and never gathered.

One item per record file, with the file's candidate components, so that a file of several
components is read once: each component's samples (read from the file by its path, or given in
memory by the caller's ``records``), its one spectra pass
(:func:`~stepframe.pipeline.selection.spectral.record_spectra`: PSA at T_1 and the misfit
periods, SD at the substitute structure's levels) and, when the run is confirmed, its simulation
at equal intensity with its overturning scan (:mod:`~stepframe.pipeline.selection.confirm`: each
candidate's scale comes from its own SD(T_1, ξ_1), so nothing waits for the others). The main
process gets numbers back: its memory holds no record, whatever the size of the catalogue, and
the records are read by as many workers as there are (a Dask cluster's too).

In a workflow the pass runs per component as the ``responses`` stage
(:mod:`stepframe.pipeline.selection.stage`), right after each file's features, and is stored:
:func:`stored` and :func:`from_stored` are its outcome as a table row and back, and
:func:`spec_digest` says which pass a stored outcome belongs to.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.core.results import Failure
from stepframe.errors import InputError
from stepframe.pipeline.selection import confirm as confirmation
from stepframe.pipeline.selection.band import FrameBand, frame_band
from stepframe.pipeline.selection.names import RECORD_SCORES
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.spectral import misfit_periods_s, record_spectra
from stepframe.pipeline.selection.substitute import SubstituteLevels, substitute_levels

Floats = NDArray[np.float64]
Samples = tuple[Floats, float]
RecordKey = tuple[str, str]


@dataclass(frozen=True)
class PassSpec:
    """What the pass computes for every component.

    Attributes
    ----------
    groups
        (periods [s], damping) groups of the spectra pass: (T_1 and the misfit periods, 0.05),
        then the substitute levels' groups.
    levels
        The substitute levels (gathers SD at every level from the groups after the first).
    record_options
        Keyword arguments of :func:`stepframe.records.read` for files read by path.
    frame
        The frame to confirm on, or None (no confirmation).
    onset_ratio
        The confirmation's equal intensity (P_1·SD(T_1)/x_c).
    """

    groups: tuple[tuple[Floats, float], ...]
    levels: SubstituteLevels
    record_options: tuple[tuple[str, Any], ...] = ()
    frame: Any = None
    onset_ratio: float = 1.0


def selection_inputs(
    frame: Any, options: SelectionOptions, record_options: Mapping[str, Any] | None
) -> tuple[FrameBand, Floats, SubstituteLevels, PassSpec | None]:
    """The frame's band, the misfit periods, the substitute levels and the pass a selection with
    ``options`` needs (None: it reads no record: a score of the fit, no scaling, target or
    confirmation)."""
    band = frame_band(
        frame,
        a_max_m=options.a_max_m,
        design_displacement_m=options.design_displacement_m,
        x_star_fraction=options.x_star_fraction,
        n_levels=options.n_levels,
    )
    periods = misfit_periods_s(options, band)
    levels = substitute_levels(band)
    needs = (
        options.confirm
        or options.scale != "none"
        or options.has_target
        or options.rank_by in RECORD_SCORES
    )
    if not needs:
        return band, periods, levels, None
    with_t1 = np.concatenate([[band.period_1_s], periods])
    spec = PassSpec(
        ((with_t1, 0.05), *levels.spectrum_groups()),
        levels,
        tuple(sorted((record_options or {}).items())),
        frame if options.confirm else None,
        options.confirm_onset_ratio if options.confirm else 1.0,
    )
    return band, periods, levels, spec


def spec_digest(spec: PassSpec) -> str:
    """sha256 of everything the pass computes from (groups, levels, record options, frame,
    onset ratio): equal digests, equal outcomes for the same record."""
    frame = spec.frame
    data = {
        "groups": [[periods.tolist(), damping] for periods, damping in spec.groups],
        "levels": spec.levels.to_dict(),
        "record_options": [list(pair) for pair in spec.record_options],
        "frame": (
            dataclasses.asdict(frame)
            if dataclasses.is_dataclass(frame) and not isinstance(frame, type)
            else repr(frame)
        ),
        "onset_ratio": spec.onset_ratio,
    }
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()


@dataclass(frozen=True)
class Component:
    """One candidate of an item: its table row, file and component, and whether the caller gave
    its samples in memory (``given``; ``samples`` None then means the caller lacks them)."""

    row: int
    file: str
    component: str
    given: bool = False
    samples: Samples | None = None

    @property
    def name(self) -> str:
        """``file [component]``, as failures name it."""
        return f"{self.file} [{self.component}]"


@dataclass(frozen=True)
class Outcome:
    """What the pass gives one component: its spectra (or the failure that stopped it) and, with
    confirmation, its equal-intensity simulation (one ``simulate_batch`` row with its scale and
    overturning ratio)."""

    row: int
    sd_5: Floats | None = None
    sd_levels: Floats | None = None
    failure: Failure | None = None
    equal: dict[str, Any] | None = None


Item = tuple[tuple[Component, ...], PassSpec]
#: A pass item's outcomes, and the samples its equal-intensity run simulated in how many seconds.
Result = tuple[list[Outcome], tuple[int, float]]
#: Components of one item at most: the simulator's batch call costs several milliseconds besides
#: its pairs, so an item's records are simulated together (each of the 25 calls of the
#: confirmation once per item, not once per record).
MAX_ITEM_COMPONENTS = 128


def items(
    table: Any,
    rows: Sequence[int],
    records: Mapping[RecordKey, Samples] | None,
    spec: PassSpec,
    workers: int,
) -> list[Item]:
    """The pass's items: the components of ``rows`` grouped by file (a file is never split), the
    files packed in order into items of about four per worker (at most
    :data:`MAX_ITEM_COMPONENTS` components), each component with its samples from ``records``
    when given (else read by path in the worker)."""
    files = table["file"].astype(str).to_numpy()
    components = table["component"].astype(str).to_numpy()
    grouped: dict[str, list[Component]] = {}
    for row in rows:
        file, component = str(files[row]), str(components[row])
        if records is None:
            member = Component(int(row), file, component)
        else:
            member = Component(int(row), file, component, True, records.get((file, component)))
        grouped.setdefault(file, []).append(member)
    size = max(1, min(MAX_ITEM_COMPONENTS, math.ceil(len(rows) / (4 * max(1, workers)))))
    out: list[Item] = []
    current: list[Component] = []
    for members in grouped.values():
        current += members
        if len(current) >= size:
            out.append((tuple(current), spec))
            current = []
    if current:
        out.append((tuple(current), spec))
    return out


def item_name(item: Item) -> str:
    """The file of an item (a failure of the whole item names it)."""
    return item[0][0].file


def read_samples(
    file: str, component: str, options: Mapping[str, Any], cache: dict[str, Any]
) -> Samples:
    """The samples of ``component`` of ``file`` (:func:`component_samples`), reading the file
    once per ``cache``.

    Raises
    ------
    InputError
        No trace of that channel in the file (or any error of the reader).
    """
    from stepframe.records import read

    if file not in cache:
        cache[file] = read(file, **dict(options))
    return component_samples(cache[file], file, component)


def component_samples(stream: Any, file: str, component: str) -> Samples:
    """The samples of the first trace of channel ``component`` in ``stream`` (read from
    ``file``): acceleration [m/s²] and dt [s].

    Raises
    ------
    InputError
        No trace of that channel.
    """
    traces = [t for t in stream if str(t.stats.channel) == component]
    if not traces:
        raise InputError(f"no channel {component!r} in the file", file)
    return np.asarray(traces[0].data, dtype=np.float64), float(traces[0].stats.delta)


def record_pass(item: Item) -> Result:
    """Worker entry: every component of one item (see the module docstring), failures kept."""
    members, spec = item
    cache: dict[str, Any] = {}
    out = []
    samples: dict[int, Samples] = {}
    for member in members:
        step = "samples"
        try:
            acc, dt = _samples(member, spec, cache)
            step = "spectra"
            sd_5, *by_group = record_spectra((acc, dt, spec.groups))
        except Exception as error:  # a batch goes on: the record lands in failures.csv
            failure = Failure.from_exception(member.name, step, error)
            out.append(Outcome(member.row, failure=failure))
            continue
        out.append(Outcome(member.row, sd_5, spec.levels.gather(by_group)))
        samples[member.row] = (acc, dt)
    cache.clear()
    if spec.frame is None:
        return out, (0, 0.0)
    return _confirmed(out, samples, spec)


def _samples(member: Component, spec: PassSpec, cache: dict[str, Any]) -> Samples:
    if not member.given:
        acc, dt = read_samples(member.file, member.component, dict(spec.record_options), cache)
    elif member.samples is None:
        raise InputError(f"no samples for {member.name}, expected them in records")
    else:
        acc, dt = member.samples
    return np.asarray(acc, dtype=np.float64), float(dt)


def _confirmed(outcomes: list[Outcome], samples: dict[int, Samples], spec: PassSpec) -> Result:
    """The outcomes with the equal-intensity simulation of each component whose SD(T_1, ξ_1)
    (the first level) gives a scale, all of the item's at once (as one batch: each pair is
    independent, so the numbers are those of any other batching)."""
    sd_t1 = np.array([o.sd_levels[0] if o.sd_levels is not None else np.nan for o in outcomes])
    usable = np.isfinite(sd_t1) & (sd_t1 > 0)
    runs = [k for k, o in enumerate(outcomes) if o.row in samples and usable[k]]
    if not runs:
        return outcomes, (0, 0.0)
    records = [samples[outcomes[k].row] for k in runs]
    sd = sd_t1[runs]
    scales = confirmation.equal_intensity_scales(sd, spec.frame, spec.onset_ratio)
    start = time.perf_counter()
    run = confirmation.run_batch(spec.frame, records, scales)
    seconds = time.perf_counter() - start
    onset = confirmation.overturn_onset_ratios(spec.frame, records, sd)
    rows = run.table.to_dict(orient="records")
    out = list(outcomes)
    for j, k in enumerate(runs):
        equal = {**rows[j], "scale": float(scales[j]), "overturn_onset_ratio": float(onset[j])}
        out[k] = dataclasses.replace(outcomes[k], equal=equal)
    return out, (sum(acc.size for acc, _ in records), seconds)


def shares(outcomes: list[Outcome], samples: dict[int, Samples], cost: tuple[int, float]) -> Floats:
    """Each outcome's share of its item's simulation time [s] (in proportion to its samples)."""
    sizes = np.array([samples[o.row][0].size if o.equal is not None else 0 for o in outcomes])
    total = sizes.sum()
    return sizes * (cost[1] / total) if total else np.zeros(len(outcomes))


def stored(outcome: Outcome, digest: str, simulated: tuple[int, float]) -> dict[str, Any]:
    """A successful outcome as a table row: its spectra as lists, its equal-intensity run as
    JSON (Python's float text reads back to the same double), and the samples it simulated in
    how many seconds."""
    assert outcome.sd_5 is not None and outcome.sd_levels is not None
    equal = ""
    if outcome.equal is not None:
        plain = {k: v.item() if hasattr(v, "item") else v for k, v in outcome.equal.items()}
        equal = json.dumps(plain)
    return {
        "spec": digest,
        "sd_5": outcome.sd_5.tolist(),
        "sd_levels": outcome.sd_levels.tolist(),
        "equal": equal,
        "simulated_samples": int(simulated[0]),
        "simulated_s": float(simulated[1]),
    }


def from_stored(row: int, values: Mapping[str, Any]) -> tuple[Outcome, tuple[int, float]]:
    """The outcome of table row ``row`` from its stored form, and what its simulation cost."""
    equal = json.loads(values["equal"]) if values["equal"] else None
    outcome = Outcome(
        row,
        np.asarray(values["sd_5"], dtype=np.float64),
        np.asarray(values["sd_levels"], dtype=np.float64),
        None,
        equal,
    )
    return outcome, (int(values["simulated_samples"]), float(values["simulated_s"]))
