"""The exact stepping simulator against its roofline, and where the difference goes (issue 29).

Run: ``python bench/simulator_roofline.py [--repeat 5]``. Prints Markdown tables for
docs/benchmarks.md. One numba thread throughout (per-core rates).

Cases: the confirmation's runs of ``stepframe select --confirm`` (bench/selection_confirmation.py):
the 100 FEMA P695 components, each scaled to equal PSA at T_1 so that the linear frame's peak
P_1·SD(T_1, ξ_1) is ``ratio``·x_c, on Example 4's frame (ratio 1) and the wide frame (ratio 2,
:func:`selection_confirmation.frames`), with no free tail, as ``simulate_batch(..., pairs="zip")``
runs them (with its default 10-s free tail); and the same pairs at a twentieth of those scales
(no stepping) beside them.

Roofline: :func:`roofline`, a tight numba loop of the same linear recurrence, the unstepped phase's
ẍ + 2ξ₁ω₁ẋ + ω₁²x = -P₁ẍ_g with ẍ_g linear over each sample (the Nigam-Jennings coefficients
of :func:`stepframe.records.spectra.nigam_jennings_coefficients`, the simulator's own solution of
that phase), scaling the record on the fly and keeping the peak |x|: the least work per sample any
integrator of this model does. Rates count the samples of every pair, record and tail (a run that
overturns stops there; the simulator is charged for the whole record, as the issue's figures
were).

Account: every sample interval of every run is classed as the kernel classes it
(``_exact.integrate``): the fast path (unstepped or stepped, and ``_exact._fast_step`` proves
that nothing inside needs locating: the chord bound keeps x inside the phase's thresholds and
below the running peak, or x is monotone with both ends inside; one closed-form step); held on
the surface; or the slow path (events located by closed-form inflections, bracketed Newton on
ẋ = 0 and on the thresholds), split by why it was taken: the range reaches a threshold, or only
the running peak (which is then resolved between samples). The classification replays the
kernel's own test on the sampled history (running and episode peaks from the samples, which the
kernel's exceed by at most the between-sample rise: a handful of intervals); beside it, the share
of unstepped intervals the kernel's earlier a-priori envelope test passed (|x_p| + the free
vibration's amplitude below x_c and the peak). The cost of each class comes from timing runs
(per pair, median of ``--repeat`` calls of ten runs in one call of the batch kernel) and least
squares on the class counts; the slow path's parts from micro-benchmarks of the kernel's own
functions.
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import statistics
import time
from typing import Any

# One numba thread from the start: the parallel batch kernel then starts no thread pool whose
# idle threads would spin on the second core while the serial loops are timed.
os.environ["NUMBA_NUM_THREADS"] = "1"

import numba
import numpy as np

from selection_confirmation import frames
from stepframe.records.examples import fema_p695
from stepframe.records.spectra import nigam_jennings_coefficients, peak_displacements_m
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure import _exact
from stepframe.structure.simulator import DEFAULT_TAIL_S, model_of, simulate_batch
from stepframe.structure.status import INVARIANT_RTOL

ELASTIC_FACTOR = 0.05
RUNS_PER_CALL = 10


@numba.njit(cache=True)
def roofline(
    flat: np.ndarray, offsets: np.ndarray, forcing: np.ndarray, coeffs: np.ndarray
) -> np.ndarray:
    """Peak |x| of x'' + 2ξωx' + ω²x = forcing[j]·a(t) for each record j of ``flat``."""
    out = np.empty(forcing.size)
    for j in range(forcing.size):
        c = coeffs[j]
        f = forcing[j]
        x = 0.0
        v = 0.0
        peak = 0.0
        prev = flat[offsets[j]] * f
        for i in range(offsets[j] + 1, offsets[j + 1]):
            cur = flat[i] * f
            x_next = c[0] * x + c[1] * v + c[4] * prev + c[5] * cur
            v = c[2] * x + c[3] * v + c[6] * prev + c[7] * cur
            x = x_next
            prev = cur
            peak = max(peak, abs(x))
        out[j] = peak
    return out


@numba.njit(cache=True)
def roofline_copying(
    flat: np.ndarray, offsets: np.ndarray, forcing: np.ndarray, coeffs: np.ndarray
) -> np.ndarray:
    """:func:`roofline` on a scaled copy of each record, as the batch kernel makes one."""
    out = np.empty(forcing.size)
    for j in range(forcing.size):
        a = flat[offsets[j] : offsets[j + 1]] * forcing[j]
        c = coeffs[j]
        x = 0.0
        v = 0.0
        peak = 0.0
        for i in range(1, a.size):
            x_next = c[0] * x + c[1] * v + c[4] * a[i - 1] + c[5] * a[i]
            v = c[2] * x + c[3] * v + c[6] * a[i - 1] + c[7] * a[i]
            x = x_next
            peak = max(peak, abs(x))
        out[j] = peak
    return out


@numba.njit(cache=True)
def roofline_exact_peak(
    flat: np.ndarray, offsets: np.ndarray, forcing: np.ndarray, coeffs: np.ndarray,
    dts: np.ndarray, w1: float, xi1: float,
) -> np.ndarray:  # fmt: skip
    """:func:`roofline` with the peak resolved between samples, as the simulator must: where ẋ
    changes sign inside an interval, the extremum is located by the kernel's own bracketed
    Newton on the interval's closed form (``_exact._segment``, ``_root``, ``_x_at``). What
    exact peak tracking costs at least in the unstepped phase (a bound, not a kernel: two sign
    changes of ẋ inside one interval, which the kernel's inflections catch, are not looked for).
    """
    out = np.empty(forcing.size)
    beta = xi1 * w1
    k = w1 * w1
    disc = w1 * w1 * (xi1 - 1.0) * (xi1 + 1.0)
    for j in range(forcing.size):
        c = coeffs[j]
        f = forcing[j]
        dt = dts[j]
        x = 0.0
        v = 0.0
        peak = 0.0
        prev = flat[offsets[j]] * f
        for i in range(offsets[j] + 1, offsets[j + 1]):
            cur = flat[i] * f
            x_next = c[0] * x + c[1] * v + c[4] * prev + c[5] * cur
            v_next = c[2] * x + c[3] * v + c[6] * prev + c[7] * cur
            if (v > 0.0 and v_next < 0.0) or (v < 0.0 and v_next > 0.0):
                # The recurrence's forcing is -a (Nigam-Jennings' sign), the segment's q₀ + q₁σ.
                seg = _exact._segment(beta, k, disc, -prev, (prev - cur) / dt, x, v)
                top = _exact._x_at(seg, _exact._root(seg, 0.0, dt, 0.0, 1))
                peak = max(peak, abs(top))
            x = x_next
            v = v_next
            prev = cur
            peak = max(peak, abs(x))
        out[j] = peak
    return out


@numba.njit(cache=True)
def classify(
    ag: np.ndarray, dt: float, hist_x: np.ndarray, hist_v: np.ndarray, hist_p: np.ndarray,
    n_steps: int, model: Any, tol_x: float,
) -> np.ndarray:  # fmt: skip
    """Interval counts by class (module docstring): fast unstepped, fast stepped, held on the
    surface, slow near a threshold, slow for the peak only; then the fast ones passed by the
    monotone test, and the unstepped ones the earlier envelope test passed."""
    w1, w2, p1, p2, g1, xi1, xi2, xc, _, xcap = model
    counts = np.zeros(7, dtype=np.int64)
    beta1, k1 = xi1 * w1, w1 * w1
    disc1 = w1 * w1 * (xi1 - 1.0) * (xi1 + 1.0)
    bound1 = _exact._bound_constants(beta1, k1, disc1, dt)
    beta2, k2 = xi2 * w2, -w2 * w2
    disc2 = w2 * w2 * (xi2 * xi2 + 1.0)
    bound2 = _exact._bound_constants(beta2, k2, disc2, dt)
    lim_x, lim_cap = xc - tol_x, xcap - tol_x
    peak = abs(hist_x[0])
    ep_peak = abs(hist_x[0])
    n_rec = ag.size - 1
    for i in range(n_steps):
        x = hist_x[i]
        v = hist_v[i]
        phase = hist_p[i]
        peak = max(peak, abs(x))
        # The episode's peak from its samples (from x_c at its lift-off).
        ep_peak = max(ep_peak, abs(x)) if phase != 0 and i > 0 and hist_p[i - 1] != 0 else xc
        if phase == 2 or phase == -2:
            counts[2] += 1
            continue
        ag_a = ag[i] if i < n_rec else 0.0
        ag_b = ag[i + 1] if i < n_rec else 0.0
        slope = (ag_b - ag_a) / dt
        if phase == 0:
            step = (x, v, -p1 * ag_a, -p1 * slope, beta1, k1, bound1,
                    -lim_x, lim_x)  # fmt: skip
            top = peak
            # The envelope test of the kernel before: |x_p| + M_0 < min(x_c, peak).
            b_p = -p1 * slope / k1
            a_p = (-p1 * ag_a - 2.0 * beta1 * b_p) / k1
            y0 = x - a_p
            q = v - b_p + beta1 * y0
            m = max(abs(a_p), abs(a_p + b_p * dt))
            counts[6] += math.sqrt(y0 * y0 + q * q / -disc1) < min(xc, peak) - m
        else:
            s = 1.0 if phase > 0 else -1.0
            lo, hi = (xc + tol_x, lim_cap) if phase > 0 else (-lim_cap, -xc - tol_x)
            step = (x, v, -s * g1 - p2 * ag_a, -p2 * slope, beta2, k2, bound2,
                    lo, hi)  # fmt: skip
            top = ep_peak
        kind = _exact._fast_step(*step, top)[2]
        if kind != 0:
            counts[0 if phase == 0 else 1] += 1
            counts[5] += kind == 2
        elif _exact._fast_step(*step, math.inf)[2] == 0:
            counts[3] += 1  # slow even with no peak to keep: its range reaches a threshold
        else:
            counts[4] += 1
    return counts


@numba.njit(cache=True)
def micro_inflections(n: int, dt: float, w1: float, xi1: float) -> float:
    """Set up a slow interval n times: phase coefficients, segment, inflections (an array)."""
    total = 0.0
    for i in range(n):
        beta, k, disc, q0, q1 = _exact._phase_coeffs(
            0, w1, 0.6445, 1.19, 1.27, 0.1387, xi1, 0.0, 0.3 + 1e-9 * i, 2.0
        )
        seg = _exact._segment(beta, k, disc, q0, q1, 0.05, 0.1)
        total += _exact._inflections(seg, dt).size
    return total


@numba.njit(cache=True)
def micro_state(n: int, dt: float, w1: float, xi1: float) -> float:
    """n evaluations of x(σ) of a segment (one exp, one sin, one cos)."""
    beta, k, disc, q0, q1 = _exact._phase_coeffs(
        0, w1, 0.6445, 1.19, 1.27, 0.1387, xi1, 0.0, 0.3, 2
    )
    seg = _exact._segment(beta, k, disc, q0, q1, 0.05, 0.1)
    total = 0.0
    for i in range(n):
        total += _exact._x_at(seg, dt * (0.5 + 1e-9 * i))
    return total


@numba.njit(cache=True)
def micro_root(n: int, w1: float, xi1: float) -> float:
    """n threshold crossings located by the kernel's bracketed Newton."""
    beta, k, disc, q0, q1 = _exact._phase_coeffs(
        0, w1, 0.6445, 1.19, 1.27, 0.1387, xi1, 0.0, 0.3, 2
    )
    seg = _exact._segment(beta, k, disc, q0, q1, 0.0, 0.2)
    hi = 0.1
    target = _exact._x_at(seg, 0.5 * hi)
    total = 0.0
    for i in range(n):
        total += _exact._root(seg, 0.0, hi, target * (1.0 + 1e-12 * (i % 7)), 0)
    return total


def _median_time(function: Any, repeat: int) -> float:
    """Median CPU time of this thread over ``repeat`` calls [s] (steadier than wall time on a
    shared machine; the work is single-threaded)."""
    times = []
    for _ in range(repeat):
        start = time.thread_time()
        function()
        times.append(time.thread_time() - start)
    return statistics.median(times)


def _run_many(model: Any, ag: np.ndarray, dt: float, n_tail: int) -> None:
    """``RUNS_PER_CALL`` runs of one pair in one call of the batch kernel (summaries only): the
    Python call's own cost, tens of µs, shared out so that it does not drown a run's slow
    intervals in its noise."""
    out = np.empty((RUNS_PER_CALL, 10))
    _exact.integrate_batch(
        ag, np.array([0, ag.size]), np.zeros(RUNS_PER_CALL, dtype=np.int64),
        np.ones(RUNS_PER_CALL), np.array([dt]), np.array([n_tail]), np.array([*model, 0.0, 0.0]),
        out,
    )  # fmt: skip


def _run(model: Any, ag: np.ndarray, dt: float, n_tail: int, history: bool) -> tuple[Any, ...]:
    """One ``_exact.integrate`` run, as ``simulate_batch`` makes it; histories when asked."""
    n_hist = ag.size + n_tail if history else 0
    hist = (np.empty(n_hist), np.empty(n_hist), np.zeros(n_hist, dtype=np.int8))
    events = (np.empty(4096), np.empty(4096, dtype=np.int8), *(np.empty(4096) for _ in range(3)))
    res = _exact.integrate(ag, dt, n_tail, *model, 0.0, 0.0, *hist, *events)
    return res, hist


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    stream, _ = fema_p695()
    series = [
        (tr.data.astype(float) * STANDARD_GRAVITY_M_S2, float(tr.stats.delta)) for tr in stream
    ]
    # The free tail of simulate_batch's default, as zero ground acceleration for the roofline.
    tails = [math.ceil(DEFAULT_TAIL_S / dt - 1e-9) for _, dt in series]
    padded = [np.concatenate([a, np.zeros(n)]) for (a, _), n in zip(series, tails, strict=True)]
    flat = np.concatenate(padded)
    offsets = np.zeros(len(series) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([a.size for a in padded])
    n_samples = int(flat.size)
    dts = np.array([dt for _, dt in series])
    throughput_rows = []
    account_rows = []
    for name, (frame, ratio) in frames().items():
        model = model_of(frame)
        t1 = 2 * math.pi / frame.omega_1_rad_s
        sd = np.array([peak_displacements_m(a, dt, [t1], frame.xi_1)[0] for a, dt in series])
        confirm = ratio * frame.x_c_m / (frame.p_1 * sd)
        coeffs = np.stack(
            [nigam_jennings_coefficients(np.array([frame.omega_1_rad_s]), frame.xi_1, dt)[0]
             for _, dt in series]
        )  # fmt: skip
        for label, scales in (
            (f"confirmation, {ratio:g} × onset", confirm),
            (f"elastic ({ELASTIC_FACTOR:g} × those scales)", ELASTIC_FACTOR * confirm),
        ):
            forcing = -frame.p_1 * scales

            batch = functools.partial(simulate_batch, frame, series, scales, pairs="zip")

            table = batch()
            roofline(flat, offsets, forcing, coeffs)
            roofline_copying(flat, offsets, forcing, coeffs)
            t_sim = _median_time(batch, args.repeat)
            t_roof = _median_time(
                functools.partial(roofline, flat, offsets, forcing, coeffs), args.repeat
            )
            t_copy = _median_time(
                functools.partial(roofline_copying, flat, offsets, forcing, coeffs), args.repeat
            )
            exact_peak = functools.partial(
                roofline_exact_peak, flat, offsets, forcing, coeffs, dts, frame.omega_1_rad_s,
                frame.xi_1,
            )  # fmt: skip
            exact_peak()
            t_peak = _median_time(exact_peak, args.repeat)
            throughput_rows.append(
                (name, label, int((table["n_stepping_episodes"] > 0).sum()),
                 int(table["overturned"].sum()), int(table["n_impacts"].sum()),
                 n_samples / t_sim, n_samples / t_roof, n_samples / t_copy, n_samples / t_peak,
                 t_sim / t_roof)
            )  # fmt: skip
            # Account: per-pair times against the class counts of its intervals.
            counts = np.zeros((len(series), 8))
            times = np.zeros(len(series))
            for j, (acc, dt) in enumerate(series):
                ag = acc * scales[j]
                res, hist = _run(model, ag, dt, tails[j], history=True)
                last = padded[j].size - 1
                steps = min(round(float(res[11]) / dt), last) if res[6] else last
                counts[j, :7] = classify(
                    padded[j] * scales[j], dt, *hist, steps, tuple(model),
                    INVARIANT_RTOL * max(frame.x_c_m, frame.x_star_m),
                )  # fmt: skip
                counts[j, 7] = res[1]
                times[j] = (
                    _median_time(functools.partial(_run_many, model, ag, dt, tails[j]), args.repeat)
                    / RUNS_PER_CALL
                )
            account_rows.append((name, label, counts, times))
    print("| frame | runs | stepping / overturned / impacts | simulator [samples/s/core] | "
          "roofline | roofline on a scaled copy | roofline, exact peak | simulator / roofline "
          "time |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    for name, label, stepping, over, impacts, *rates, ratio in throughput_rows:
        cells = " | ".join(f"{r:.3g}" for r in rates)
        print(f"| {name} | {label} | {stepping} / {over} / {impacts} | {cells} | {ratio:.1f} |")
    print(
        f"\nSamples per batch: {n_samples:,} (100 pairs, records and {DEFAULT_TAIL_S:g}-s tails).\n"
    )
    _account(account_rows, throughput_rows)
    _micro(frames()["Example 4"][0])


def _account(rows: list[Any], throughput: list[Any]) -> None:
    """Least-squares cost of each interval class and event, and the time shares they make."""
    all_counts = np.concatenate([c for _, _, c, _ in rows])
    all_times = np.concatenate([t for _, _, _, t in rows])

    def grouped(counts: np.ndarray) -> np.ndarray:
        """Fast (either phase), held, slow (near a threshold or for the peak), events."""
        return np.column_stack([counts[:, 0] + counts[:, 1], counts[:, 2],
                                counts[:, 3] + counts[:, 4], counts[:, 7]])  # fmt: skip

    # Per-run constant (the call, its allocations), then one cost per class and per event.
    design = np.column_stack([np.ones(all_times.size), grouped(all_counts)])
    cost, *_ = np.linalg.lstsq(design, all_times, rcond=None)
    fitted = design @ cost
    r2 = 1 - np.sum((all_times - fitted) ** 2) / np.sum((all_times - all_times.mean()) ** 2)
    roof_ns = 1e9 / statistics.median(r[6] for r in throughput)  # the roofline's rate
    names = ("per run", "fast interval", "held interval", "slow interval", "event")
    print(f"Cost per item (least squares over {all_times.size} runs, R² = {r2:.3f}); "
          f"roofline sample: {roof_ns:.2f} ns.\n")  # fmt: skip
    print("| item | cost [ns] | in roofline samples |")
    print("|---|---|---|")
    for item, value in zip(names, cost, strict=True):
        print(f"| {item} | {1e9 * value:,.1f} | {1e9 * value / roof_ns:,.1f} |")
    print("\n| frame | runs | fast: unstepped / stepped (by the monotone test) | held | slow "
          "near a threshold | slow for the peak | events per 1,000 intervals | time: fast / held "
          "/ slow / events | unstepped fast by the envelope test (before) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    for name, label, counts, _ in rows:
        sums = counts.sum(axis=0)
        total = sums[:5].sum()
        pct = 100 * sums / total
        parts = grouped(sums[None, :])[0] * cost[1:]
        split = " / ".join(f"{100 * v / parts.sum():.0f} %" for v in parts)
        print(f"| {name} | {label} | {pct[0]:.1f} % / {pct[1]:.1f} % ({pct[5]:.1f} %) | "
              f"{pct[2]:.1f} % | {pct[3]:.2f} % | {pct[4]:.2f} % | {1000 * sums[7] / total:.1f} | "
              f"{split} | {pct[6]:.1f} % |")  # fmt: skip
    print(f"\n(measured total of these runs: {1e3 * all_times.sum():.1f} ms; model "
          f"{1e3 * fitted.sum():.1f} ms)\n")  # fmt: skip


def _micro(frame: Any) -> None:
    """Costs of the slow path's parts, from the kernel's own functions in tight loops."""
    n = 2_000_000
    w1, xi1, dt = frame.omega_1_rad_s, frame.xi_1, 0.01
    micro_inflections(10, dt, w1, xi1)
    micro_state(10, dt, w1, xi1)
    micro_root(10, w1, xi1)
    rows = (
        ("phase coefficients + segment + inflections (allocates an array)",
         _median_time(lambda: micro_inflections(n, dt, w1, xi1), 3)),
        ("x(σ) of a segment (exp, sin, cos)", _median_time(lambda: micro_state(n, dt, w1, xi1), 3)),
        ("threshold crossing by bracketed Newton", _median_time(lambda: micro_root(n, w1, xi1), 3)),
    )  # fmt: skip
    print("| slow-path part (Example 4 frame, unstepped phase) | ns per call |")
    print("|---|---|")
    for label, seconds in rows:
        print(f"| {label} | {1e9 * seconds / n:.1f} |")


if __name__ == "__main__":
    main()
