"""Why the gap diagnosis named what it named on cases of the independent blind-check
battery: every refit's decision with the figures its rule was judged on, and every
calibration done again (issue 27's LSA rig; the figures docs/gap-diagnosis.md quotes from
cases it read again after a run).

Run:  .venv/bin/python benchmarks/case_decisions.py SPEC -g GEAR PLAN:SEED:RATIO:FORMS ...
      [--record RECORD]   (FORMS "none" and RATIO "none" for a no-effect case, two forms
      joined by "+" for a pair, ":beyond-gain" after a crosstalk sized beyond the gain;
      about 30 s a case on the LSA rig; a sealed case only with the record of its one run)

e.g.  .venv/bin/python benchmarks/case_decisions.py campaigns/lsa-main-gear-rig/campaign.yaml \\
          -g main-right D:31:2.0:gain-skew S1:7507:none:none

Each case's noisy campaign is written as the battery writes it
(:func:`blind_independent.noisy_case`) and diagnosed (:func:`certkit.gap.selection.diagnose`)
as a battery run diagnoses it; nothing is scored or recorded.  The first line printed says
who ran this script (commit, diagnosis code, date, command).  A sealed case is read only
after its one run: its record must be given and hold it.
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
    parser.add_argument("cases", nargs="+", help="PLAN:SEED:RATIO:FORMS[:beyond-gain]")
    parser.add_argument("--record", type=Path, default=None,
                        help="the record of the sealed run whose cases are read (a sealed "
                             "case is read only after its one run)")
    args = parser.parse_args()
    template = str(Path(args.spec).resolve())
    settings = battery.own.Settings()
    cases = battery.cases_read(parser, args.cases)
    ran = set()
    if args.record is not None:
        ran = {o["id"] for o in battery.read_blind_check(args.record).cases}
    unrun = [t for t, c in zip(args.cases, cases)
             if c.plan.battery == "sealed" and c.id not in ran]
    if unrun:
        parser.error(f"{', '.join(unrun)}: sealed, and not in a record given with --record: "
                     "a sealed case is read only after its one run")
    print(battery.reader_line(" ".join(
        ["python", "benchmarks/case_decisions.py", Path(args.spec).name, "-g", args.gear,
         *args.cases] + (["--record", str(args.record)] if args.record else []))), flush=True)
    for text, case in zip(args.cases, cases):
        with tempfile.TemporaryDirectory() as folder:
            try:
                written = battery.noisy_case(template, args.gear, case, settings,
                                             Path(folder))
            except ValueError as error:
                print(f"{text}: {error}", flush=True)
                continue
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
