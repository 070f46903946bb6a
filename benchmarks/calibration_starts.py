"""How far the nominal calibration from the spec's values stops from the best fit of its
parameters, on cases of the independent blind-check battery, and what the gap diagnosis's
further starts (:mod:`certkit.physics.starts`) find (issue 27's LSA rig).

Run:  .venv/bin/python benchmarks/calibration_starts.py SPEC -g GEAR PLAN:SEED:RATIO:FORM ...
      [--starts N]   (FORM "none" and RATIO "none" for a no-effect case; about 15 s a case)

e.g.  .venv/bin/python benchmarks/calibration_starts.py campaigns/lsa-main-gear-rig/campaign.yaml \\
          -g main-right S5:14402:2.0:gain-skew S5:14402:5.0:gain-skew S5:14401:5.0:gain-skew \\
          S5:14401:2.0:gain-skew S4:12800:none:none

Each case's noisy campaign is written as the battery writes it
(:func:`blind_independent.noisy_case`); the nominal model (no effect) is calibrated on the
diagnosis's training runs from the spec's values alone, then with N further starts
(default :data:`certkit.gap.selection.NOMINAL_STARTS`, as the diagnosis calibrates it),
and the training costs are printed with the start kept and the knobs' values of both.
"""

from __future__ import annotations

import blas_threads  # noqa: F401 -- first: pins the BLAS threads before numpy is loaded

# isort: split
import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import blind_independent as battery  # noqa: E402

from certkit.gap.holdout import split_for  # noqa: E402
from certkit.gap.selection import NOMINAL_STARTS  # noqa: E402
from certkit.physics.calibration import calibrate_gear  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spec")
    parser.add_argument("-g", "--gear", required=True)
    parser.add_argument("cases", nargs="+", help="PLAN:SEED:RATIO:FORM")
    parser.add_argument("--starts", type=int, default=NOMINAL_STARTS)
    args = parser.parse_args()
    template = str(Path(args.spec).resolve())
    settings = battery.own.Settings()
    cases = battery.cases_read(parser, args.cases)
    for text, case in zip(args.cases, cases):
        with tempfile.TemporaryDirectory() as folder:
            written = battery.load_campaign(battery.noisy_case(
                template, args.gear, case, settings, Path(folder)))
            training = list(split_for(written, args.gear)[0])
            first = calibrate_gear(written, args.gear, effects=[], run_ids=training)
            best = calibrate_gear(written, args.gear, effects=[], run_ids=training,
                                  starts=args.starts)
        names = [k.name for k in first.knobs]
        search = best.search
        kept = "the spec's values" if search.kept is None else f"start {search.kept + 1}"
        costs = ", ".join("failed" if c is None else f"{c:.5g}" for c in search.start_costs)
        print(f"{text}: from the spec's values {first.fit.cost:.5g}; {args.starts} further "
              f"starts' fits {costs}; kept: {kept}, {best.fit.cost:.5g}")
        for name, a, b in zip(names, first.fit.estimate, best.fit.estimate):
            print(f"    {name}: {a:.6g} -> {b:.6g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
