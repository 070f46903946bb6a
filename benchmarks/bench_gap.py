"""Wall time of the gap diagnosis and of a 40-case blind check (issue 5's targets:
diagnosis of the example campaign <= 30 s; a 40-case blind check <= 10 min on 2 cores).

Run:  .venv/bin/python benchmarks/bench_gap.py [--runs N] [--cases K] [--skip-blind]

The diagnosis is timed as a user meets it: `certkit gap SPEC` in a fresh process (every
recorded gear unit; imports and compiled-code loading count), N times, median quoted.  The
blind check runs K cases spread evenly over the default battery (single-effect cases at
every ratio, no-effect and two-effect cases alike) on the local process pool, once, and
prints its wall time and each case's; this machine is shared, so quote medians and say
what else was running.
"""

from __future__ import annotations

import blas_threads  # first: pins the BLAS threads before numpy is loaded

# isort: split
import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--cases", type=int, default=40)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--skip-blind", action="store_true")
    parser.add_argument("--campaign", type=Path,
                        default=REPO / "campaigns" / "seed-amphibian" / "campaign.yaml")
    args = parser.parse_args()
    times = []
    for index in range(args.runs):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "certkit.cli", "gap", str(args.campaign)],
                       check=True, capture_output=True)
        times.append(time.perf_counter() - start)
        print(f"certkit gap, run {index + 1}: {times[-1]:.2f} s")
    print(f"certkit gap (every gear unit): median {statistics.median(times):.2f} s over "
          f"{args.runs} runs (target <= 30 s)")
    if args.skip_blind:
        return

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from blindcheck.battery import battery, blind_check

    print(f"thread pools of this process: {blas_threads.loaded_pools()}")

    everything = battery()
    picked = [everything[round(i * (len(everything) - 1) / max(args.cases - 1, 1))]
              for i in range(args.cases)]

    def progress(outcome):
        print(f"  {outcome['id']}: {time.perf_counter() - start:.1f} s")

    with tempfile.TemporaryDirectory():
        start = time.perf_counter()
        document = blind_check(args.campaign, cases=picked, workers=args.workers,
                               progress=progress)
        wall = time.perf_counter() - start
    print(f"blind check, {len(picked)} cases: {wall:.1f} s wall ({wall / 60:.2f} min; "
          f"target <= 10 min), {wall / len(picked):.2f} s per case")
    top1 = document["metrics"]["top1"]
    print(f"  (top-1 on its {top1['cases']} scored single-effect cases: "
          f"{top1['value'] if top1['value'] is None else round(100 * top1['value'])} %)")


if __name__ == "__main__":
    main()
