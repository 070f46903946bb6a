"""Why the gap diagnosis named what it named on cases of the independent blind-check
battery: every refit's decision with the figures its rule was judged on, and every
calibration done again (issue 27's LSA rig; the figures docs/gap-diagnosis.md quotes from
cases it read again after a run).

Run:  .venv/bin/python benchmarks/case_decisions.py SPEC -g GEAR PLAN:SEED:RATIO:FORM ...
      (FORM "none" and RATIO "none" for a no-effect case; about 30 s a case on the LSA rig)

e.g.  .venv/bin/python benchmarks/case_decisions.py campaigns/lsa-main-gear-rig/campaign.yaml \\
          -g main-right D:31:2.0:gain-skew S1:7507:none:none

Each case's noisy campaign is written as the battery writes it
(:func:`blind_independent.noisy_case`) and diagnosed (:func:`certkit.gap.selection.diagnose`)
as a battery run diagnoses it; nothing is scored or recorded.  A sealed case read this way
is read after its one run, never before it.
"""

from __future__ import annotations

if __name__ == "__main__":     # run as the benchmark (a test imports it as a library)
    import blas_threads  # noqa: F401 -- first: pins the BLAS threads before numpy is loaded

# isort: split
import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import blind_independent as battery  # noqa: E402

from certkit.gap.selection import diagnose  # noqa: E402


def _figures(figures: dict) -> str:
    return ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                     for k, v in figures.items() if not isinstance(v, dict))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spec")
    parser.add_argument("-g", "--gear", required=True)
    parser.add_argument("cases", nargs="+", help="PLAN:SEED:RATIO:FORM")
    args = parser.parse_args()
    template = str(Path(args.spec).resolve())
    settings = battery.own.Settings()
    for text in args.cases:
        case = battery.case_named(text)
        with tempfile.TemporaryDirectory() as folder:
            written = battery.noisy_case(template, args.gear, case, settings, Path(folder))
            found = diagnose(battery.load_campaign(written), args.gear)
        costs = ", ".join(f"{c:.5g}" for c in found.step_costs)
        print(f"{text} ({case.id}): named {' + '.join(found.answer) or 'nothing'}; "
              f"training cost before each step {costs}", flush=True)
        for decision in found.recalibrated:
            figures = {k: v for k, v in decision.figures.items() if k != "from"}
            print(f"    {decision.rule}, from {decision.name}'s parameters: "
                  f"{_figures(figures)}")
        for step, decisions in enumerate(found.refit_decisions, start=1):
            for decision in decisions:
                print(f"    step {step}: {decision.name}: {decision.rule} "
                      f"({_figures(decision.figures)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
