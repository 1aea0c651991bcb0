"""The exact integrator's results on the roofline's runs, dumped and compared between versions.

Run: ``python bench/exact_identity.py dump OUT.npz`` with one version of stepframe importable
(e.g. ``PYTHONPATH=/tmp/old/src`` for a ``git archive`` of another commit), the same with the
other, then ``python bench/exact_identity.py compare A.npz B.npz``: the largest difference of every
output (peak |x| and its time, end state, overturning time, counts, every event's time, kind,
speeds and episode peak) over all runs, and the runs that differ in counts or status.

Runs: those of ``bench/simulator_roofline.py`` (the 100 FEMA P695 components at equal PSA(T_1),
Example 4's frame at the onset of stepping and the wide frame at twice it, with the default 10-s
tail; and the same at a twentieth of the scale), plus the same pairs at 0.3, 3 and 6 times the
confirmation's scale (more impacts, overturns): each through ``_exact.integrate`` with its full
history and event arrays, as ``simulate`` runs it.
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from selection_confirmation import frames
from stepframe.records.examples import fema_p695
from stepframe.records.spectra import peak_displacements_m
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure import _exact
from stepframe.structure.simulator import DEFAULT_TAIL_S, model_of

FACTORS = (1.0, 0.05, 0.3, 3.0, 6.0)
N_EVENTS = 20_000
SUMMARY = ("status", "n_events", "n_liftoffs", "n_impacts", "peak", "t_peak", "overturned",
           "t_overturn", "x_end", "v_end", "phase_end", "t_end")  # fmt: skip


def dump(path: str) -> None:
    """Every run's summary, history and events into ``path``."""
    stream, _ = fema_p695()
    series = [
        (tr.data.astype(float) * STANDARD_GRAVITY_M_S2, float(tr.stats.delta)) for tr in stream
    ]
    out: dict[str, np.ndarray] = {}
    for name, (frame, ratio) in frames().items():
        model = model_of(frame)
        t1 = 2 * math.pi / frame.omega_1_rad_s
        for j, (acc, dt) in enumerate(series):
            sd = peak_displacements_m(acc, dt, [t1], frame.xi_1)[0]
            confirm = ratio * frame.x_c_m / (frame.p_1 * sd)
            n_tail = math.ceil(DEFAULT_TAIL_S / dt - 1e-9)
            for factor in FACTORS:
                n = acc.size + n_tail
                hist = (np.empty(n), np.empty(n), np.zeros(n, dtype=np.int8))
                events = (np.empty(N_EVENTS), np.empty(N_EVENTS, dtype=np.int8),
                          *(np.empty(N_EVENTS) for _ in range(3)))  # fmt: skip
                res = _exact.integrate(
                    acc * (confirm * factor), dt, n_tail, *model, 0.0, 0.0, *hist, *events
                )
                key = f"{name}|{factor:g}|{j}"
                out[key + "|summary"] = np.array(res, dtype=float)
                n_ev = min(int(res[1]), N_EVENTS)
                out[key + "|events"] = np.column_stack([e[:n_ev].astype(float) for e in events])
                out[key + "|x"] = hist[0]
    np.savez_compressed(path, **out)
    print(f"{path}: {len(out) // 3} runs")


def compare(path_a: str, path_b: str) -> None:
    """Largest differences between two dumps, by output, and runs whose counts differ."""
    a, b = np.load(path_a), np.load(path_b)
    keys = sorted({k.rsplit("|", 1)[0] for k in a.files})
    worst = dict.fromkeys((*SUMMARY, "event t", "event v_in", "event v_out", "event peak",
                           "history x"), 0.0)  # fmt: skip
    where: dict[str, str] = {}
    differing = []
    for key in keys:
        sa, sb = a[key + "|summary"], b[key + "|summary"]
        if any(sa[i] != sb[i] for i in (0, 1, 2, 3, 6, 10)):
            differing.append((key, sa[[0, 1, 2, 3, 6]], sb[[0, 1, 2, 3, 6]]))
            continue
        for i, label in enumerate(SUMMARY):
            d = 0.0 if (math.isnan(sa[i]) and math.isnan(sb[i])) else abs(sa[i] - sb[i])
            if d > worst[label]:
                worst[label], where[label] = d, key
        ea, eb = a[key + "|events"], b[key + "|events"]
        if ea.shape != eb.shape or np.any(ea[:, 1] != eb[:, 1]):
            differing.append((key, "event kinds", ""))
            continue
        for col, label in ((0, "event t"), (2, "event v_in"), (3, "event v_out"),
                           (4, "event peak")):  # fmt: skip
            if ea.shape[0]:
                d = float(np.max(np.abs(ea[:, col] - eb[:, col])))
                if d > worst[label]:
                    worst[label], where[label] = d, key
        d = float(np.max(np.abs(a[key + "|x"] - b[key + "|x"])))
        if d > worst["history x"]:
            worst["history x"], where["history x"] = d, key
    # By frame and scale factor: the largest event-time and relative peak differences.
    groups: dict[str, list[float]] = {}
    for key in keys:
        group = key.rsplit("|", 1)[0]
        ea, eb = a[key + "|events"], b[key + "|events"]
        d_t = float(np.max(np.abs(ea[:, 0] - eb[:, 0]))) if ea.shape == eb.shape and ea.size else 0
        pa, pb = a[key + "|summary"][4], b[key + "|summary"][4]
        row = groups.setdefault(group, [0.0, 0.0, 0.0])
        row[0] = max(row[0], d_t)
        row[1] = max(row[1], abs(pa - pb) / pa if pa > 0 else 0.0)
        row[2] += ea.shape[0]
    n_events = sum(a[k + "|events"].shape[0] for k in keys)
    print(f"{len(keys)} runs, {n_events:,} events; runs differing in status or counts: "
          f"{len(differing)}\n")  # fmt: skip
    print("| output | largest difference | run (frame, factor, record) |")
    print("|---|---|---|")
    for label, value in worst.items():
        print(f"| {label} | {value:.3g} | {where.get(label, '')} |")
    print("\n| frame, factor of the confirmation's scale | events | largest event-time "
          "difference [s] | largest peak difference (relative) |")  # fmt: skip
    print("|---|---|---|---|")
    for group, (d_t, d_p, n) in groups.items():
        print(f"| {group.replace('|', ', ')} | {n:.0f} | {d_t:.2g} | {d_p:.2g} |")
    for key, sa, sb in differing:
        print(f"differs: {key}: {sa} against {sb}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("dump").add_argument("out")
    cmp = sub.add_parser("compare")
    cmp.add_argument("a")
    cmp.add_argument("b")
    args = parser.parse_args()
    if args.command == "dump":
        dump(args.out)
    else:
        compare(args.a, args.b)


if __name__ == "__main__":
    sys.exit(main())
