"""The gap diagnosis's blind check on certkit's own battery (its own physics, the truth
forms of ``certkit.physics.effects``): a quick check any campaign can be put through.

Run:  .venv/bin/python benchmarks/blind_own.py SPEC [-g GEAR] -o DIR [--workers N]
      [--scheduler ADDRESS] [--seeds 21,22,23] [--ratios 1,2,5]

Writes DIR/blind-check.json and DIR/blind-check-cases.csv (see :mod:`blindcheck.battery`).
The independent battery, whose truths certkit did not write, is blind_independent.py; a
campaign's report should name that one's record.
"""

from __future__ import annotations

if __name__ == "__main__":
    import blas_threads  # noqa: F401 -- first: pins the BLAS threads before numpy is loaded

# isort: split
import argparse
import sys
import time as clock
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from blindcheck.battery import Settings, blind_check  # noqa: E402
from blindcheck.record import write_blind_check  # noqa: E402

from certkit.errors import CampaignError, CertkitInputError  # noqa: E402
from certkit.outputs import check_target, staged_folder  # noqa: E402


def _numbers(text: str, kind=float) -> tuple:
    try:
        values = tuple(kind(v) for v in text.split(",") if v.strip())
    except ValueError:
        values = ()
    if not values:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, found {text!r}")
    return values


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spec", type=Path)
    parser.add_argument("-g", "--gear", default=None)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--scheduler", default=None,
                        help="a dask.distributed scheduler address to run the cases on")
    parser.add_argument("--seeds", type=lambda t: _numbers(t, int), default=(21, 22, 23))
    parser.add_argument("--ratios", type=_numbers, default=(1.0, 2.0, 5.0))
    args = parser.parse_args()
    if args.workers is not None and args.workers < 1:
        parser.error(f"--workers: expected a whole number ≥ 1, found {args.workers}")
    own = {"blind-check.json", "blind-check-cases.csv"}
    started = clock.perf_counter()
    try:
        check_target(args.out, [args.spec], own)   # before the battery, which takes minutes
        document = blind_check(args.spec, args.gear, Settings(ratios=args.ratios,
                                                              seeds=args.seeds),
                               workers=args.workers, scheduler=args.scheduler,
                               progress=lambda o: print(f"{o['id']}: named "
                                                        f"{', '.join(o['named']) or '(none)'}",
                                                        flush=True))
        with staged_folder(args.out, [args.spec], own) as folder:
            write_blind_check(document, folder)
    except (CertkitInputError, CampaignError) as error:
        print(error, file=sys.stderr)
        return 2
    for name, metric in document["metrics"].items():
        value = "n/a" if metric["value"] is None else f"{100 * metric['value']:.0f} %"
        target = "" if metric["target"] is None else \
            f" (target {metric['direction']} {100 * metric['target']:.0f} %)"
        print(f"{name.replace('_', ' ')}: {value} of {metric['cases']}{target}")
    print(f"{len(document['cases'])} cases in {clock.perf_counter() - started:.0f} s; "
          f"written: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
