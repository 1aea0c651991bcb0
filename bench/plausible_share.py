"""Plausible share of features + fit on real records per time origin and ω_g estimator
(docs/stochastic-features.md).

Three sets: the embedded FEMA P695 catalogue (100 components), the shared PEER NGA-West2 records
(tests/data/peer_nga_west2) and the format files (tests/data/formats, every record file a reader
takes without a response; the raw-counts MiniSEED is left out). For each time origin and ω_g
estimator it prints a Markdown row: components, plausible, failed to run, how often the P pick
was used, and how many were refused because ω_r lies below the usable band (the estimator's
floor or the record's lowest usable frequency).

    python bench/plausible_share.py [--jobs 1] [--t0 start p-pick auto] [--frequency NAME ...]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from stepframe.records.examples import fema_p695
from stepframe.stochastic.catalog_features import catalog_features

ROOT = Path(__file__).resolve().parents[1] / "tests" / "data"
_NOT_RECORDS = {".md", ".txt", ".json", ".xml", ".mseed"}


def record_files(folder: Path) -> list[Path]:
    """Record files under ``folder`` (documentation, responses and raw counts left out)."""
    return sorted(
        p for p in folder.rglob("*") if p.is_file() and p.suffix.lower() not in _NOT_RECORDS
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--t0", nargs="+", default=["start", "p-pick", "auto"])
    parser.add_argument("--frequency", nargs="+", default=["zero-crossing"])
    args = parser.parse_args()
    stream, meta = fema_p695()
    sets = {
        "FEMA P695": (stream, list(meta["lowest_usable_frequency_hz"])),
        "PEER NGA-West2": (record_files(ROOT / "peer_nga_west2"), None),
        "format files": (record_files(ROOT / "formats"), None),
    }
    print(
        "| set | t0 | ω_g by | components | plausible | share | failed to run | P pick used "
        "| ω_r below the usable band |"
    )
    print("|---" * 9 + "|")
    for name, (source, lows) in sets.items():
        for t0 in args.t0:
            for frequency in args.frequency:
                table, failures = catalog_features(
                    source, n_jobs=args.jobs, t0=t0, lowest_usable_hz=lows, frequency=frequency
                )
                n, ok = len(table), int(table["plausible"].sum())
                used = int(table["p_onset_used"].sum())
                below = int(table["implausible_reason"].str.contains("below usable band").sum())
                print(
                    f"| {name} | {t0} | {frequency} | {n} | {ok} | {ok / max(n, 1):.0%} "
                    f"| {len(failures)} | {used} | {below} |"
                )


if __name__ == "__main__":
    main()
