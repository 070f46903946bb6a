"""The measurement-uncertainty stage's speed, against its target (issue 28): Monte Carlo with
10⁵ trials for every verdict of the seed example in at most 3 s on 2 cores.

Run:  .venv/bin/python benchmarks/bench_uncertainty.py [--runs N] [--campaign PATH]

Prints, for each campaign (both examples by default; medians of ``--runs`` runs in this
process after one warm-up, BLAS threads pinned to one):

* the Monte Carlo part alone: the draws, every verdict's margins for all of them, the
  check of the vectorised model against the engine and the summaries;
* the whole stage (the GUM's engine runs included): ``budgets``;
* the verdicts it covered by Monte Carlo and the trials each.

The machine is shared and noisy: quote the medians.
"""

from __future__ import annotations

import blas_threads  # noqa: F401  first: pins the BLAS threads of the timed commands

# isort: split
import argparse
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from certkit import load_campaign  # noqa: E402
from certkit.compliance.engine import evaluate  # noqa: E402
from certkit.compliance.verdict_uncertainty import TRIALS, budgets  # noqa: E402

EXAMPLES = (REPO / "campaigns" / "seed-amphibian" / "campaign.yaml",
            REPO / "campaigns" / "lsa-main-gear-rig" / "campaign.yaml")
#: The target, on the seed example (issue 28).
TARGET_SECONDS = 3.0


def measure(path: Path, runs: int) -> dict:
    campaign = load_campaign(path)
    assessment = evaluate(campaign)
    budgets(assessment, evaluate)                     # warm-up: imports, caches
    whole, monte_carlo = [], []
    for _ in range(runs):
        started = time.perf_counter()
        found = budgets(assessment, evaluate)
        whole.append(time.perf_counter() - started)
        monte_carlo.append(found.monte_carlo_seconds)
    covered = sum(1 for item in found.verdicts.values()
                  if item.monte_carlo_interval is not None)
    return {"whole": statistics.median(whole), "monte_carlo": statistics.median(monte_carlo),
            "covered": covered, "margins": len(found.verdicts),
            "verdicts": len(assessment.verdicts)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--campaign", type=Path, action="append")
    args = parser.parse_args()
    for path in args.campaign or EXAMPLES:
        figures = measure(path, args.runs)
        verdict = ("met" if figures["monte_carlo"] <= TARGET_SECONDS else "NOT met")
        print(f"{path.parent.name}: Monte Carlo ({TRIALS} trials for each of "
              f"{figures['covered']} of the {figures['margins']} verdicts with a margin; "
              f"{figures['verdicts']} verdicts in all) "
              f"{figures['monte_carlo']:.3f} s median of {args.runs} "
              f"(target ≤ {TARGET_SECONDS:g} s: {verdict}); the whole stage with the GUM's "
              f"engine runs {figures['whole']:.3f} s")


if __name__ == "__main__":
    main()
