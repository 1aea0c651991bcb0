"""A synthetic catalogue the size of PEER NGA-West2, as AT2 files, generated once and cached.

21,500 records of two horizontal components each (43,000 AT2 files, one component per file as
PEER distributes them), written by the project's own generator
(:func:`stepframe.stochastic.synthetic.synthetic_motions`: the eq. 6.12 process times its
envelope). Each record has its own Beck-Papadimitriou model, drawn around its event's, and its two
components are two realisations of it. Lengths are 20-80 s (uniform), sampling 0.005, 0.01 or
0.02 s (40/40/20 %): about 6,500 samples per component on average, 4.3 GB of AT2 text.

Files go to ``bench/out/nga/<name>/`` (ignored by git), and ``bench/out/nga/<name>.json`` is
written last, so an interrupted generation is resumed (files already written are kept) and a
complete one is reused.
Every file is a function of its record number only (the seed), so any subset is reproducible.

Run: ``python bench/nga_catalogue.py`` (the 43,000; about 15 minutes on 2 cores) or
``python bench/nga_catalogue.py --records 500 --name small``.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import time
from pathlib import Path

import numpy as np

OUT = Path(__file__).parent / "out" / "nga"
#: Records per event (NGA-West2: about 21,500 records of about 600 events).
RECORDS_PER_EVENT = 36
DT_CHOICES_S = (0.005, 0.01, 0.02)
DT_WEIGHTS = (0.4, 0.4, 0.2)
COMPONENTS = ("000", "090")


def record_files(number: int) -> dict[str, bytes]:
    """The two AT2 files of record ``number`` (file name → bytes); a function of ``number``."""
    from stepframe.pipeline.catalogue.example_files import at2_bytes
    from stepframe.records.units import STANDARD_GRAVITY_M_S2
    from stepframe.stochastic.model import GroundMotionModel
    from stepframe.stochastic.synthetic import synthetic_motions

    event = number // RECORDS_PER_EVENT
    event_rng = np.random.default_rng([event, 1])
    rng = np.random.default_rng([number, 2])
    # The event's dominant frequencies, then the site's variation around them (log-normal).
    wp = math.exp(event_rng.uniform(math.log(15), math.log(60))) * math.exp(rng.normal(0, 0.15))
    wr = math.exp(event_rng.uniform(math.log(2.5), math.log(0.6 * wp)))
    wr = min(wr * math.exp(rng.normal(0, 0.15)), 0.8 * wp)
    ws = wr + (wp - wr) * rng.uniform(0.05, 0.6)
    duration_s = rng.uniform(20.0, 80.0)
    t_max = rng.uniform(0.08, 0.2) * duration_s
    t_dur = t_max + rng.uniform(0.25, 0.45) * duration_s
    dt_s = float(rng.choice(DT_CHOICES_S, p=DT_WEIGHTS))
    model = GroundMotionModel(
        wp, ws, wr, rng.uniform(0.1, 0.6), rng.uniform(0.1, 0.6), t_max, t_dur
    )
    peak_m_s2 = math.exp(rng.uniform(math.log(0.05), math.log(3.0)))
    _, acc = synthetic_motions(
        model,
        duration_s=duration_s,
        dt_s=dt_s,
        n_realisations=len(COMPONENTS),
        seed=number,
        peak_intensity=peak_m_s2,
    )
    month, day = 1 + event % 12, 1 + event % 28
    year = 1970 + event % 50
    event_text = f"EQ{event:04d}, {month}/{day}/{year}"
    station = f"STA{number % 997:04d}"
    return {
        f"RSN{number + 1}_{station}_{component}.AT2": at2_bytes(
            acc[k] / STANDARD_GRAVITY_M_S2, dt_s, component, event_text, station
        )
        for k, component in enumerate(COMPONENTS)
    }


def _write_record(job: tuple[int, str]) -> int:
    number, folder = job
    written = 0
    for name, data in record_files(number).items():
        target = Path(folder) / name
        if not target.is_file():
            temporary = target.with_suffix(".part")
            temporary.write_bytes(data)
            temporary.rename(target)
        written += 1
    return written


def build(folder: Path, numbers: range, workers: int = 2) -> Path:
    """Write records ``numbers`` into ``folder`` (resuming), then ``<folder>.json``; the folder."""
    done = folder.with_suffix(".json")
    if done.is_file() and json.loads(done.read_text())["records"] == [numbers.start, numbers.stop]:
        return folder
    folder.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    jobs = [(number, str(folder)) for number in numbers]
    with multiprocessing.get_context("fork").Pool(workers) as pool:
        files = sum(pool.imap_unordered(_write_record, jobs, chunksize=16))
    seconds = time.perf_counter() - start
    size = sum(p.stat().st_size for p in folder.glob("*.AT2"))
    done.write_text(
        json.dumps(
            {
                "records": [numbers.start, numbers.stop],
                "files": files,
                "bytes": size,
                "seconds": round(seconds, 1),
            }
        )
    )
    return folder


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=21_500, help="records (two files each)")
    parser.add_argument("--first", type=int, default=0, help="number of the first record")
    parser.add_argument("--name", default="records", help="folder under bench/out/nga/")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    folder = build(OUT / args.name, range(args.first, args.first + args.records), args.workers)
    print(json.loads(folder.with_suffix(".json").read_text()))


if __name__ == "__main__":
    main()
