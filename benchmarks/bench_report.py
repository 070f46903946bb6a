"""Wall time of `certkit report` on the example campaign.

Run:  .venv/bin/python benchmarks/bench_report.py [--runs N] [--campaign PATH]

Times the full report (with the governing-equation model: calibration of every gear
unit against its runs, overlays) and the compliance report alone (`--no-model`; issue 2's
target: median <= 5 s).  Each run is a fresh process, so imports count, as they do for a
user.  Prints every run and the medians; this machine is shared, so quote the medians.
"""

from __future__ import annotations

import blas_threads  # noqa: F401  first: pins the BLAS threads of the timed commands

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
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--campaign", type=Path,
                        default=REPO / "campaigns" / "seed-amphibian" / "campaign.yaml")
    args = parser.parse_args()
    name = (args.campaign.relative_to(REPO) if args.campaign.is_relative_to(REPO)
            else args.campaign)
    for label, options, target in (("full report", [], ""),
                                   ("compliance only (--no-model)", ["--no-model"],
                                    " (target <= 5 s)")):
        times = []
        with tempfile.TemporaryDirectory() as folder:
            for index in range(args.runs):
                out = Path(folder) / f"out{index}"
                start = time.perf_counter()
                subprocess.run([sys.executable, "-m", "certkit.cli", "report", str(args.campaign),
                                "-o", str(out), *options], check=True, capture_output=True)
                times.append(time.perf_counter() - start)
                print(f"{label}, run {index + 1}: {times[-1]:.2f} s")
        print(f"certkit report {name}, {label}: median {statistics.median(times):.2f} s, "
              f"min {min(times):.2f} s, max {max(times):.2f} s over {args.runs} runs{target}")


if __name__ == "__main__":
    main()
