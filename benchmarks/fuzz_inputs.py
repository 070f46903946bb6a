"""Fuzz certkit's loaders with hostile and careless input; count clean errors and crashes.

Run:  .venv/bin/python benchmarks/fuzz_inputs.py [--examples N] [--chain N] [--seed S]

Drives the strategies of tests/hostile_inputs.py (the property tests run a few hundred of
them, derandomised, in the suite) for longer, with random seeds:

* quantity parser: parse_quantity and parse_unit on generated quantity and unit text;
* spec loader: load_campaign on mutated example specs (values replaced with hostile ones,
  text inserted or deleted, lines dropped or repeated);
* data loader: load_campaign on the analytic campaign with its CSV mutated (cells,
  columns, bytes, cuts, time rescaled), half of them with every data check waived;
* Parquet loader: load_campaign and assess on the analytic run written as Parquet and
  mutated (column types, nulls, odd, repeated, non-text and two-level names, the time as
  timestamps, an index, zero rows, row groups of one row or of all, bytes overwritten,
  the file cut), half of them with every data check waived;
* validate -> assess chain: spec mutations that the loader accepts are assessed (audit
  rows, results document) and, for the drop-model campaign, simulated;
* validate -> assess -> drop model: the drop-model campaign simulated (250 Hz, cheap
  identification settings: tests/hostile_inputs.py, MODELLED_SETTINGS), its spec or one
  run's CSV mutated, through what ``certkit report`` runs: assessment, calibration,
  identification and, for the first --gap accepted inputs, the gap diagnosis. This is
  slow (about 6 s per accepted input, 40 s more with the gap diagnosis, on an idle core;
  three in four are refused at load), hence its own, small count.

A crash is any exception other than certkit's own input errors (CertkitInputError,
CampaignError, QuantityError).  Prints per loader: inputs tried, accepted, clean input
errors, crashes, and the first reproducer of each kind of crash.  Exit 1 if any crashed.
"""

from __future__ import annotations

import argparse
import collections
import sys
import tempfile
import time
from pathlib import Path

from hypothesis import HealthCheck, Phase, given, seed, settings

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from tests import hostile_inputs as hostile  # noqa: E402
from certkit.units import parse_quantity, parse_unit  # noqa: E402


class Tally:
    def __init__(self, name: str):
        self.name = name
        self.counts: collections.Counter = collections.Counter()
        self.first: dict[str, tuple[str, object]] = {}
        self.started = time.perf_counter()

    def add(self, kind: str, signature: str = "", detail: str = "", example=None) -> None:
        self.counts[kind] += 1
        if kind == "crash":
            self.counts[f"crash:{signature}"] += 1
            self.first.setdefault(signature, (detail, example))

    def report(self) -> None:
        tried = self.counts["ok"] + self.counts["clean"] + self.counts["crash"]
        print(f"{self.name}: {tried} inputs tried in {time.perf_counter() - self.started:.0f} s;"
              f" accepted {self.counts['ok']}, clean input errors {self.counts['clean']}, "
              f"crashes {self.counts['crash']} ({len(self.first)} kinds)")
        for signature, (detail, example) in self.first.items():
            print(f"  {self.counts['crash:' + signature]} x {detail}")
            print(f"    first reproducer: {repr(example)[:400]}")


def run(strategy, examples: int, random_seed: int, body) -> None:
    """Call ``body`` on ``examples`` draws of ``strategy`` (no shrinking: body never fails);
    none when ``examples`` is 0 (to run the other loaders only)."""
    if examples == 0:
        return
    @seed(random_seed)
    @settings(max_examples=examples, database=None, deadline=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(strategy)
    def draw(example):
        body(example)

    draw()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=10_000, help="inputs per loader")
    parser.add_argument("--chain", type=int, default=2_000,
                        help="spec mutations run through load, assess and simulate")
    parser.add_argument("--parquet", type=int, default=2_000,
                        help="Parquet mutations (about 0.1 s each)")
    parser.add_argument("--model", type=int, default=40,
                        help="mutations run through the drop-model stages")
    parser.add_argument("--gap", type=int, default=3,
                        help="accepted ones of those that get the gap diagnosis too")
    parser.add_argument("--seed", type=int, default=16)
    args = parser.parse_args()
    tallies = []

    quantities = Tally("quantity parser (parse_quantity, parse_unit)")

    def quantity(example):
        text, kind = example
        for function, what in ((parse_quantity, kind), (parse_unit, kind)):
            kind_of = hostile.outcome(function, text, what)
            quantities.add(kind_of, f"{function.__name__}", f"{function.__name__} crashed",
                           (text, what))

    from hypothesis import strategies as st
    run(st.tuples(hostile.quantity_texts(), hostile.KIND_NAMES), args.examples, args.seed,
        quantity)
    tallies.append(quantities)
    quantities.report()

    with tempfile.TemporaryDirectory() as scratch:
        folder = hostile.campaign_folder(Path(scratch) / "campaign")
        gaps = [args.gap]

        def modelled(mutation):
            result = hostile.try_model(Path(scratch) / "modelled", mutation, gap=gaps[0] > 0)
            if result.kind == "ok" and gaps[0] > 0:
                gaps[0] -= 1
            return result
        for name, strategy, attempt, count in (
                ("spec loader (load_campaign, mutated spec)", hostile.spec_mutations(),
                 lambda m: hostile.try_spec(folder, m), args.examples),
                ("data loader (load_campaign, mutated CSV)", hostile.data_mutations(),
                 lambda m: hostile.try_data(folder, m, assess=True), args.examples),
                ("Parquet loader (load_campaign and assess, mutated Parquet)",
                 hostile.parquet_mutations(), lambda m: hostile.try_data(folder, m, assess=True),
                 args.parquet),
                ("validate -> assess -> simulate (mutated spec)", hostile.spec_mutations(),
                 lambda m: hostile.try_spec(folder, m, assess=True, simulate=True),
                 args.chain),
                ("validate -> assess -> calibration, identification, gap (mutated spec or "
                 "data)", hostile.model_mutations(), modelled, args.model)):
            tally = Tally(name)

            def body(mutation, tally=tally, attempt=attempt):
                result = attempt(mutation)
                tally.add(result.kind, result.signature, result.detail, mutation)

            run(strategy, count, args.seed, body)
            tallies.append(tally)
            tally.report()
    return 1 if any(t.counts["crash"] for t in tallies) else 0


if __name__ == "__main__":
    sys.exit(main())
