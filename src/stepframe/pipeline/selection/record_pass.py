"""The selection's one pass over its candidates' records, in the workers: samples read where they
are used, and never gathered.

One item per group of record files, with the files' candidate components, so that a file of
several components is read once. For each component: its samples (read from the file by its
path, or given in memory by the caller's ``records``), its one spectra pass with its peers
(:func:`~stepframe.pipeline.selection.peers.spectra_and_peers`: PSA at T_1 and the misfit
periods, SD(T_1, ξ_1), SD at the substitute structure's levels when that score is named, the
standard intensity measures), then, when the ranking intensity is the record's own
(:meth:`PassSpec.base_scale`), its simulated response over the ranking's ladder
(:func:`~stepframe.pipeline.selection.exact.simulated_response`), and, when the run is
confirmed, its simulation at equal intensity with its overturning scan
(:mod:`~stepframe.pipeline.selection.confirm`). Each of these depends on the record alone (its
scale comes from its own spectrum), so nothing waits for the other candidates, and a component's
numbers are the same whatever it is batched with. The main process gets numbers back: its memory
holds no record, whatever the size of the catalogue, and the records are read by as many workers
as there are (a Dask cluster's too).

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
from stepframe.pipeline.selection.intensity import (
    RankingIntensity,
    equal_intensity_scales,
    ranking_intensity,
)
from stepframe.pipeline.selection.names import FIT_TIERS, SIMULATED_RESPONSE
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.peers import PeerPeriods, spectra_and_peers
from stepframe.pipeline.selection.spectral import misfit_periods_s
from stepframe.pipeline.selection.substitute import SubstituteLevels, substitute_levels
from stepframe.records.units import STANDARD_GRAVITY_M_S2

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
        (T_1, ξ_1), then the substitute levels' groups when that score is named.
    levels
        The substitute levels (gathers SD at every level from the groups after the second), or
        None (not named).
    peer_periods
        The periods the peers read.
    record_options
        Keyword arguments of :func:`stepframe.records.read` for files read by path.
    frame
        The frame the ranking and the confirmation simulate, or None (neither runs here).
    intensity
        The ranking intensity when the ranking simulates here, else None.
    scale_bounds
        (scale_min, scale_max): a record's scale factor under the scaling policy ``none``.
    ladder
        The ranking's factors on the record's base scale.
    onset_ratio
        The confirmation's equal intensity (P_1·SD(T_1)/x_c), or None (no confirmation).
    """

    groups: tuple[tuple[Floats, float], ...]
    levels: SubstituteLevels | None
    peer_periods: PeerPeriods
    record_options: tuple[tuple[str, Any], ...] = ()
    frame: Any = None
    intensity: RankingIntensity | None = None
    scale_bounds: tuple[float, float] = (1.0, 1.0)
    ladder: tuple[float, ...] = ()
    onset_ratio: float | None = None

    def base_scale(self, psa_t1_g: float, sd_t1_m: float) -> float:
        """The record's scale factor at the ranking intensity, as
        :meth:`RankingIntensity.base_scales` gives it for the whole table (elementwise: the
        same double)."""
        assert self.intensity is not None
        scale = np.clip(np.ones(1), *self.scale_bounds)
        base = self.intensity.base_scales(
            self.frame, np.array([sd_t1_m]), np.array([psa_t1_g]), scale
        )
        return float(base[0])


def needs_samples(options: SelectionOptions) -> bool:
    """Whether a selection with ``options`` reads its candidates' records (not when it ranks by
    a score of the fit with no scaling, target or confirmation)."""
    fit_only = {options.rank_by, options.prefilter} <= {*FIT_TIERS, "none", "auto"}
    return bool(
        options.confirm
        or options.scale != "none"
        or options.has_target
        or not fit_only
        or options.rank_by == SIMULATED_RESPONSE
    )


def ranks_here(options: SelectionOptions, intensity: RankingIntensity) -> bool:
    """Whether the ranking's simulations can run in the pass: the simulated response is the
    ranking and each record's scale at the ranking intensity follows from its own spectrum (an
    equal PSA(T_1), or the records as used with no scaling and no target)."""
    if options.rank_by != SIMULATED_RESPONSE:
        return False
    own = options.scale == "none" and not options.has_target and options.unit == "component"
    return intensity.kind == "equal-psa-t1" or own


def selection_inputs(
    frame: Any, options: SelectionOptions, record_options: Mapping[str, Any] | None
) -> tuple[FrameBand, Floats, SubstituteLevels, PassSpec | None]:
    """The frame's band, the misfit periods, the substitute levels and the pass a selection with
    ``options`` needs (None: it reads no record)."""
    from stepframe.pipeline.selection.exact import LADDER

    band = frame_band(
        frame,
        a_max_m=options.a_max_m,
        design_displacement_m=options.design_displacement_m,
        x_star_fraction=options.x_star_fraction,
        n_levels=options.n_levels,
    )
    periods = misfit_periods_s(options, band)
    levels = substitute_levels(band)
    if not needs_samples(options):
        return band, periods, levels, None
    substitute = "substitute_demand_ratio" in {options.rank_by, options.prefilter, *options.scores}
    with_t1 = np.concatenate([[band.period_1_s], periods])
    groups = (
        (with_t1, 0.05),
        (np.array([band.period_1_s]), frame.xi_1),
        *(levels.spectrum_groups() if substitute else ()),
    )
    intensity = ranking_intensity(options, frame, LADDER)
    ranked = ranks_here(options, intensity)
    spec = PassSpec(
        groups,
        levels if substitute else None,
        PeerPeriods(band.period_1_s, 2.0 * math.pi / band.omega_low_rad_s),
        tuple(sorted((record_options or {}).items())),
        frame if (ranked or options.confirm) else None,
        intensity if ranked else None,
        (options.scale_min, options.scale_max),
        LADDER if ranked else (),
        options.confirm_onset_ratio if options.confirm else None,
    )
    return band, periods, levels, spec


def spec_digest(spec: PassSpec) -> str:
    """sha256 of everything the pass computes from: equal digests, equal outcomes for the same
    record."""
    frame = spec.frame
    data = {
        "groups": [[periods.tolist(), damping] for periods, damping in spec.groups],
        "levels": spec.levels.to_dict() if spec.levels is not None else None,
        "peers": [spec.peer_periods.period_1_s, spec.peer_periods.band_end_s],
        "record_options": [list(pair) for pair in spec.record_options],
        "frame": (
            dataclasses.asdict(frame)
            if dataclasses.is_dataclass(frame) and not isinstance(frame, type)
            else repr(frame)
        ),
        "intensity": spec.intensity.to_dict() if spec.intensity is not None else None,
        "scale_bounds": list(spec.scale_bounds),
        "ladder": list(spec.ladder),
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
    """What the pass gives one component.

    Attributes
    ----------
    row
        The component's table row.
    sd_5
        SD [m] at T_1 and the misfit periods, 5 % damping.
    sd_t1_m
        SD(T_1, ξ_1) [m].
    sd_levels
        SD [m] at the substitute levels (None: not named).
    peers
        The standard intensity measures (:data:`~stepframe.pipeline.selection.peers.PEERS`).
    npts, dt_s
        The record's samples and sampling interval [s] (the ranking's cost estimate).
    failure
        What stopped the pass for this component (then nothing else is set).
    ranked
        The ranking's simulation (``base``, ``response_m``, ``overturn_factor``, ``peak_m``,
        ``overturned``, ``n_overturned``, ``failed``), or None (not run here).
    equal
        The equal-intensity simulation (one ``simulate_batch`` row with its scale and
        overturning ratio), or None (no confirmation, or no positive SD(T_1, ξ_1)).
    seconds
        Its share of the item's ranking and equal-intensity simulations [s].
    """

    row: int
    sd_5: Floats | None = None
    sd_t1_m: float = math.nan
    sd_levels: Floats | None = None
    peers: dict[str, float] | None = None
    npts: int = 0
    dt_s: float = math.nan
    failure: Failure | None = None
    ranked: dict[str, Any] | None = None
    equal: dict[str, Any] | None = None
    seconds: tuple[float, float] = (0.0, 0.0)


Item = tuple[tuple[Component, ...], PassSpec]
#: Components of one item at most: the simulator's batch call costs several milliseconds besides
#: its pairs, so an item's records are simulated together.
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
        if records is not None and (file, component) in records:
            member = Component(int(row), file, component, True, records[(file, component)])
        else:  # a file beside the mapping's records (a folder beside the example): by path
            member = Component(int(row), file, component)
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
    from stepframe.pipeline.catalogue.stage import read_kwargs
    from stepframe.records.io import read_measured

    if file not in cache:  # raw counts after the standard processing, as every output
        cache[file] = read_measured(file, **read_kwargs(dict(options)))
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


def record_pass(item: Item) -> list[Outcome]:
    """Worker entry: every component of one item (see the module docstring), failures kept."""
    members, spec = item
    cache: dict[str, Any] = {}
    out = []
    samples: dict[int, Samples] = {}
    for k, member in enumerate(members):
        step = "samples"
        try:
            acc, dt = _samples(member, spec, cache)
            step = "spectra"
            (sd_5, sd_1, *by_group), peers = spectra_and_peers(
                (acc, dt, spec.groups, spec.peer_periods)
            )
        except Exception as error:  # a batch goes on: the record lands in failures.csv
            failure = Failure.from_exception(member.name, step, error)
            out.append(Outcome(member.row, failure=failure))
            continue
        sd_levels = spec.levels.gather(by_group) if spec.levels is not None else None
        out.append(
            Outcome(member.row, sd_5, float(sd_1[0]), sd_levels, peers, int(acc.size), float(dt))
        )
        samples[k] = (acc, dt)
    cache.clear()
    ranking_s = _ranked(out, samples, spec)
    equal_s = _confirmed(out, samples, spec)
    return [
        dataclasses.replace(o, seconds=(float(ranking_s[k]), float(equal_s[k])))
        for k, o in enumerate(out)
    ]


def _samples(member: Component, spec: PassSpec, cache: dict[str, Any]) -> Samples:
    if not member.given:
        acc, dt = read_samples(member.file, member.component, dict(spec.record_options), cache)
    elif member.samples is None:
        raise InputError(f"no samples for {member.name}, expected them in records")
    else:
        acc, dt = member.samples
    return np.asarray(acc, dtype=np.float64), float(dt)


def _shares(runs: list[int], samples: dict[int, Samples], seconds: float, n: int) -> Floats:
    """``seconds`` shared among the outcomes ``runs`` in proportion to their samples."""
    out = np.zeros(n)
    sizes = np.array([samples[k][0].size for k in runs], dtype=np.float64)
    if sizes.sum() > 0:
        out[runs] = sizes * (seconds / sizes.sum())
    return out


def _ranked(outcomes: list[Outcome], samples: dict[int, Samples], spec: PassSpec) -> Floats:
    """Fill in each outcome's ranking simulation (at its own base scale, a finite one) when the
    ranking runs here; each one's share of the time it took [s]."""
    from stepframe.pipeline.selection.exact import simulated_response

    if spec.intensity is None:
        return np.zeros(len(outcomes))
    from stepframe.records.spectra import pseudo_acceleration_m_s2

    bases = {}
    for k in samples:
        sd_5 = outcomes[k].sd_5
        assert sd_5 is not None
        # PSA(T_1) as the selection table has it (run.py)
        psa_t1_g = pseudo_acceleration_m_s2(spec.groups[0][0], sd_5)[0] / STANDARD_GRAVITY_M_S2
        base = spec.base_scale(psa_t1_g, outcomes[k].sd_t1_m)
        if math.isfinite(base):
            bases[k] = base
    runs = sorted(bases)
    if not runs:
        return np.zeros(len(outcomes))
    start = time.perf_counter()
    response = simulated_response(
        spec.frame, [samples[k] for k in runs], np.array([bases[k] for k in runs]), spec.ladder
    )
    seconds = time.perf_counter() - start
    for j, k in enumerate(runs):
        outcomes[k] = dataclasses.replace(
            outcomes[k],
            ranked={
                "base": bases[k],
                "response_m": float(response.response_m[j]),
                "overturn_factor": float(response.overturn_factor[j]),
                "peak_m": float(response.peak_m[j]),
                "overturned": bool(response.overturned[j]),
                "n_overturned": int(response.n_overturned[j]),
                "failed": response.failed[j],
            },
        )
    return _shares(runs, samples, seconds, len(outcomes))


def _confirmed(outcomes: list[Outcome], samples: dict[int, Samples], spec: PassSpec) -> Floats:
    """Fill in the equal-intensity simulation of each outcome whose SD(T_1, ξ_1) gives a scale,
    all of the item's at once (each pair is independent, so the numbers are those of any other
    batching); each one's share of the time it took [s]."""
    if spec.onset_ratio is None:
        return np.zeros(len(outcomes))
    runs = [k for k in samples if math.isfinite(outcomes[k].sd_t1_m) and outcomes[k].sd_t1_m > 0]
    if not runs:
        return np.zeros(len(outcomes))
    records = [samples[k] for k in runs]
    sd = np.array([outcomes[k].sd_t1_m for k in runs])
    scales = equal_intensity_scales(sd, spec.frame, spec.onset_ratio)
    start = time.perf_counter()
    run = confirmation.run_batch(spec.frame, records, scales)
    seconds = time.perf_counter() - start
    onset = confirmation.overturn_onset_ratios(spec.frame, records, sd)
    rows = run.table.to_dict(orient="records")
    for j, k in enumerate(runs):
        equal = {**rows[j], "scale": float(scales[j]), "overturn_onset_ratio": float(onset[j])}
        outcomes[k] = dataclasses.replace(outcomes[k], equal=equal)
    return _shares(runs, samples, seconds, len(outcomes))


def _plain(value: Any) -> Any:
    return value.item() if hasattr(value, "item") else value


def stored(outcome: Outcome, digest: str) -> dict[str, Any]:
    """A successful outcome as a table row of scalars (the store compares rows): its spectra
    and simulations as JSON (Python's float text reads back to the same double)."""
    assert outcome.sd_5 is not None and outcome.peers is not None
    extra = {
        "peers": {k: _plain(v) for k, v in outcome.peers.items()},
        "ranked": outcome.ranked,
        "equal": (
            {k: _plain(v) for k, v in outcome.equal.items()} if outcome.equal is not None else None
        ),
    }
    return {
        "spec": digest,
        "sd_5": json.dumps(outcome.sd_5.tolist()),
        "sd_t1_m": outcome.sd_t1_m,
        "sd_levels": json.dumps(
            outcome.sd_levels.tolist() if outcome.sd_levels is not None else []
        ),
        "npts": outcome.npts,
        "dt_s": outcome.dt_s,
        "simulations": json.dumps(extra),
        "ranking_s": outcome.seconds[0],
        "equal_s": outcome.seconds[1],
    }


def from_stored(row: int, values: Mapping[str, Any]) -> Outcome:
    """The outcome of table row ``row`` from its stored form (:func:`stored`)."""
    extra = json.loads(values["simulations"])
    levels = np.asarray(json.loads(values["sd_levels"]), dtype=np.float64)
    return Outcome(
        row,
        np.asarray(json.loads(values["sd_5"]), dtype=np.float64),
        float(values["sd_t1_m"]),
        levels if levels.size else None,
        {k: float(v) for k, v in extra["peers"].items()},
        int(values["npts"]),
        float(values["dt_s"]),
        None,
        extra["ranked"],
        extra["equal"],
        (float(values["ranking_s"]), float(values["equal_s"])),
    )
