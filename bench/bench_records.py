"""Benchmark of the records stage: response spectra, RotD50, catalogue table, `records info`.

Prints Markdown tables (paste into docs/benchmarks.md, section "Records"). Peers measured in the
same run: a plain-numpy time-stepping reference (the same exact recurrence, vectorised over
periods, Python loop over time) and pyrotd (frequency-domain, if installed; not a dependency).
Timings are medians of repeated runs on one thread; the machine's 2 cores are shared with other
work, so absolute numbers are noisy, ratios less so.

Run: ``python bench/bench_records.py``
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# Thread limits above must be set before numpy loads, hence the imports below them.
import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from fresh_process import fresh_process_walls
from stepframe.records import read
from stepframe.records.catalog import intensity_table
from stepframe.records.examples import fema_p695
from stepframe.records.rotd import rotd_spectrum
from stepframe.records.spectra import (
    nigam_jennings_coefficients,
    response_spectrum,
    upsample,
    upsampling_factors,
)
from timing import median_cpu_seconds, median_seconds

PEER = Path(__file__).parents[1] / "tests" / "data" / "peer_nga_west2"


def numpy_reference_psa(acc: np.ndarray, dt: float, periods: np.ndarray, damping: float) -> Any:
    """Plain numpy: the same recurrence and upsampling, vectorised over periods only."""
    out = np.empty(periods.size)
    factors = upsampling_factors(periods, dt)
    for factor in np.unique(factors):
        index = np.flatnonzero(factors == factor)
        fine = upsample(acc, int(factor))
        c = nigam_jennings_coefficients(2 * np.pi / periods[index], damping, dt / factor).T
        u = np.zeros(index.size)
        v = np.zeros(index.size)
        peak = np.zeros(index.size)
        for i in range(1, fine.size):
            u, v = (
                c[0] * u + c[1] * v + c[4] * fine[i - 1] + c[5] * fine[i],
                c[2] * u + c[3] * v + c[6] * fine[i - 1] + c[7] * fine[i],
            )
            np.maximum(peak, np.abs(u), out=peak)
        out[index] = peak * (2 * np.pi / periods[index]) ** 2
    return out / 9.80665


def main() -> None:
    reference = json.loads((PEER / "RSN8883_peer_spectra.json").read_text())
    periods = np.array(reference["period"])
    peer5 = next(s for s in reference["spectra"] if s["damping"] == 0.05)
    h1, h2 = (read(PEER / name)[0].data for name in reference["fnames"])
    dt = 0.005
    assert h1.size == 16396

    def error(psa_g: np.ndarray, key: str, spectrum: dict[str, Any] = peer5) -> str:
        return f"{100 * np.max(np.abs(psa_g / np.array(spectrum[key]) - 1)):.2f} %"

    rows: list[tuple[str, str, str, str]] = []
    response_spectrum(h1, dt, periods)  # compile or load the numba cache
    ours = median_seconds(lambda: response_spectrum(h1, dt, periods), 21)
    ours_cpu = median_cpu_seconds(lambda: response_spectrum(h1, dt, periods), 21)
    ours_psa = response_spectrum(h1, dt, periods).psa_g
    rows.append(
        ("stepframe `nigam_jennings` (numba)", f"{1e3 * ours:.1f} ms", "1", error(ours_psa, "h1"))
    )
    fd = median_seconds(lambda: response_spectrum(h1, dt, periods, method="frequency_domain"), 5)
    fd_psa = response_spectrum(h1, dt, periods, method="frequency_domain").psa_g
    rows.append(
        (
            "stepframe `frequency_domain`",
            f"{1e3 * fd:.1f} ms",
            f"{fd / ours:.0f}",
            error(fd_psa, "h1"),
        )
    )
    ref = median_seconds(lambda: numpy_reference_psa(h1, dt, periods, 0.05), 3)
    ref_psa = numpy_reference_psa(h1, dt, periods, 0.05)
    rows.append(
        (
            "plain-numpy time stepping (same recurrence)",
            f"{1e3 * ref:.0f} ms",
            f"{ref / ours:.0f}",
            error(ref_psa, "h1"),
        )
    )
    try:
        import pyrotd  # type: ignore[import-untyped]

        freqs = 1 / periods
        h1_g = h1 / 9.80665  # pyrotd returns the input's units
        pyrotd_time = median_seconds(lambda: pyrotd.calc_spec_accels(dt, h1_g, freqs, 0.05), 5)
        pyrotd_psa = np.asarray(pyrotd.calc_spec_accels(dt, h1_g, freqs, 0.05).spec_accel)
        rows.append(
            (
                f"pyrotd {pyrotd.__version__} `calc_spec_accels`",
                f"{1e3 * pyrotd_time:.0f} ms",
                f"{pyrotd_time / ours:.0f}",
                error(pyrotd_psa, "h1"),
            )
        )
    except ImportError:
        pyrotd = None
    print("### PSA of RSN 8883 h1 (16,396 samples, dt 0.005 s), 111 PEER periods, 5 % damping\n")
    print("| method | time per component (median) | ratio to stepframe | max error vs PEER h1 |")
    print("|---|---|---|---|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    target = "met" if ours_cpu <= 0.020 else "MISSED"
    print(
        f"\nTarget ≤ 20 ms per component on one core: {target} (CPU time of the thread "
        f"{1e3 * ours_cpu:.1f} ms, median of 21; wall {1e3 * ours:.1f} ms).\n"
    )

    print("### RotD50 of RSN 8883 (two components, 111 periods, 180 angles)\n")
    print("| method | damping | time (median) | max error vs PEER RotD50 |")
    print("|---|---|---|---|")
    for spectrum in reference["spectra"]:
        zeta = spectrum["damping"]
        rotd_time = median_seconds(lambda z=zeta: rotd_spectrum(h1, h2, dt, periods, z), 3)
        result = rotd_spectrum(h1, h2, dt, periods, zeta)
        err = error(result.in_g("rotd50"), "rotd50", spectrum)
        print(f"| stepframe | {zeta} | {rotd_time:.2f} s | {err} |")
        if pyrotd is not None:
            call = lambda z=zeta: pyrotd.calc_rotated_spec_accels(  # noqa: E731
                dt, h1 / 9.80665, h2 / 9.80665, 1 / periods, z, percentiles=[50]
            )
            peer_time = median_seconds(call, 1)
            rotd50 = np.asarray(call().spec_accel)
            print(f"| pyrotd | {zeta} | {peer_time:.2f} s | {error(rotd50, 'rotd50', spectrum)} |")

    start = time.perf_counter()
    stream, _ = fema_p695()
    loaded = time.perf_counter() - start
    table = intensity_table(stream)
    total = time.perf_counter() - start
    print("\n### Example catalogue (100 FEMA P695 components): full intensity-measure table\n")
    print("| quantity | value |")
    print("|---|---|")
    print(f"| load the example catalogue | {loaded:.2f} s |")
    print(f"| load + table of {len(table)} rows x {len(table.columns)} columns | {total:.2f} s |")
    cold_code = (
        "from stepframe.records.examples import fema_p695;"
        "from stepframe.records.catalog import intensity_table;"
        "intensity_table(fema_p695()[0])"
    )
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", cold_code], check=True)
    cold = time.perf_counter() - start
    print(f"| same in a fresh process, imports and numba cache load included | {cold:.2f} s |")
    print(f"| target < 10 s | {'met' if max(total, cold) < 10 else 'MISSED'} |")

    command = [
        sys.executable,
        "-m",
        "stepframe.cli",
        "records",
        "info",
        str(PEER / reference["fnames"][0]),
    ]
    first, wall = fresh_process_walls(command)
    print("\n### `stepframe records info` on one AT2 file (fresh process each run)\n")
    print("| quantity | value |")
    print("|---|---|")
    print(f"| first run | {first:.2f} s |")
    print(f"| median of the next 5 | {wall:.2f} s |")
    print(f"| target < 1.5 s | {'met' if wall < 1.5 else 'MISSED'} |")


if __name__ == "__main__":
    main()
