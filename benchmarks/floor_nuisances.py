"""What sets the nominal model's floor on a rig: the floor of no-effect cases of the
independent blind-check battery (the held-out load RMSE of the nominal model calibrated,
as the gap diagnosis calibrates it, on the case's noise-free records) with the independent
simulator's nuisance physics as drawn, and with each of them removed in turn (issue 27's
LSA rig; docs/gap-diagnosis.md).

Run:  .venv/bin/python benchmarks/floor_nuisances.py SPEC -g GEAR PLAN:SEED:none:none ...
      (about 2 minutes a case on the LSA rig: five calibrations from 8 further starts)

e.g.  .venv/bin/python benchmarks/floor_nuisances.py campaigns/lsa-main-gear-rig/campaign.yaml \\
          -g main-right S1:7507:none:none D:505:none:none

The nuisances (:class:`truthgen.Nuisances`): the top-out pad's compression under preload,
the real-gas coefficient, the tyre curve's departure from a power law.  "rigid pad" sets
the pad's compression to 0 (a near-rigid stop), "none" all three.  The case's scatter of
the nominal values and its contact phases stay as drawn.
"""

from __future__ import annotations

if __name__ == "__main__":     # run as the benchmark
    import blas_threads  # noqa: F401 -- first: pins the BLAS threads before numpy is loaded

# isort: split
import argparse
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import blind_independent as battery  # noqa: E402
from blindcheck.plans import draws  # noqa: E402
from blindcheck.truth_gap import held_out_load  # noqa: E402

from certkit.gap.holdout import split_for  # noqa: E402
from certkit.gap.selection import NOMINAL_STARTS  # noqa: E402
from certkit.physics.calibration import calibrate_gear  # noqa: E402
from certkit.physics.synthetic import NO_SENSOR_EFFECTS  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spec")
    parser.add_argument("-g", "--gear", required=True)
    parser.add_argument("cases", nargs="+", help="PLAN:SEED:none:none")
    args = parser.parse_args()
    template = str(Path(args.spec).resolve())
    cases = battery.cases_read(parser, args.cases)
    if any(c.forms for c in cases) or any(c.plan.battery == "sealed" for c in cases):
        parser.error("no-effect cases of the development battery only")
    print(battery.reader_line(" ".join(["python", "benchmarks/floor_nuisances.py",
                                        Path(args.spec).name, "-g", args.gear,
                                        *args.cases])), flush=True)
    for text, case in zip(args.cases, cases):
        _, drawn = draws(case.key, case.forms, case.plan)
        variants = {"drawn": drawn, "no real gas": replace(drawn, gas=0.0),
                    "no tyre shape": replace(drawn, tyre_shape=0.0),
                    "rigid pad": replace(drawn, pad=0.0),
                    "none": replace(drawn, gas=0.0, tyre_shape=0.0, pad=0.0)}
        floors = []
        for label, nuisances in variants.items():
            with tempfile.TemporaryDirectory() as folder:
                bare = battery.load_campaign(battery.write_case(
                    template, args.gear, case, (), Path(folder), NO_SENSOR_EFFECTS, "bare",
                    nuisances))
                training, held = split_for(bare, args.gear)[:2]
                calibration = calibrate_gear(bare, args.gear, effects=[],
                                             run_ids=list(training), starts=NOMINAL_STARTS)
                floor = held_out_load(bare, args.gear, held, calibration.apply)
                floors.append(f"{label} {floor:.1f} N (training cost "
                              f"{calibration.fit.cost:.4g})")
        print(f"{text} (pad {drawn.pad * 1e3:.2f} mm, real gas {drawn.gas:.3f}, tyre shape "
              f"{drawn.tyre_shape:.3f}): {'; '.join(floors)}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
