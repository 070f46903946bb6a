"""Drop simulation speed: the batched fast path against the scipy reference, at equal accuracy.

Run:  .venv/bin/python benchmarks/bench_simulation.py [--drops N] [--repeats R]

The gear is the example campaign's left main gear (campaigns/seed-amphibian), drop
heights spread over 200-300 mm, 2 s records at 1 kHz output.  Two configurations: the
nominal drop model (gas spring, orifice, stops, tyre: what calibration and the gap
diagnosis start from) and the campaign's model with its effects (rebound orifice, seal
friction).  For each: drops per second of one batched call (compiled RK4, both cores),
the scipy LSODA reference per drop, the speed ratio, and the largest difference in peak
load and maximum stroke between the two paths.  Medians of the repeats.
Target (issue 3): >= 500 drops/s and >= 50x.
"""

from __future__ import annotations

import blas_threads  # first: pins the BLAS threads before numpy is loaded

# isort: split
import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from certkit import load_campaign
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import simulate_batch, simulate_reference

G = 9.80665
SPEC = Path(__file__).resolve().parent.parent / "campaigns" / "seed-amphibian" / "campaign.yaml"


def measure(model, velocities, repeats: int, reference_drops: int) -> dict:
    simulate_batch(model, velocities[:2], duration=0.01)   # load the compiled kernel
    rates = []
    for _ in range(repeats):
        start = time.perf_counter()
        batch = simulate_batch(model, velocities, duration=2.0)
        rates.append(velocities.size / (time.perf_counter() - start))
    seconds, peak_error, stroke_error = [], 0.0, 0.0
    for index in np.linspace(0, velocities.size - 1, reference_drops).astype(int):
        start = time.perf_counter()
        reference = simulate_reference(model, float(velocities[index]), duration=2.0, lead=0.0)
        seconds.append(time.perf_counter() - start)
        peak_error = max(peak_error, abs(batch.load[index].max() / reference.load.max() - 1))
        stroke_error = max(stroke_error,
                           abs(batch.stroke[index].max() / reference.stroke.max() - 1))
    return {"rate": statistics.median(rates), "all": rates,
            "reference": statistics.median(seconds), "peak": peak_error, "stroke": stroke_error}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--drops", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--reference-drops", type=int, default=5)
    args = parser.parse_args()
    campaign = load_campaign(SPEC)
    print(f"thread pools: {blas_threads.loaded_pools()}")
    run = campaign.spec.runs[-1]
    velocities = np.sqrt(2 * G * np.linspace(0.2, 0.3, args.drops))
    for label, effects in (("nominal model", []), ("with the campaign's effects",
                                                    list(campaign.spec.model.effects))):
        model = drop_model_for(campaign.spec, run, "left-main", effects=effects)
        result = measure(model, velocities, args.repeats, args.reference_drops)
        runs = ", ".join(f"{r:.0f}" for r in result["all"])
        print(f"{label} ({', '.join(effects) or 'no optional effects'}):")
        print(f"  fast path: median {result['rate']:.0f} drops/s over {args.repeats} batches of "
              f"{args.drops} ({runs})")
        print(f"  reference (scipy LSODA, rtol 1e-9): median {result['reference']:.3f} s per drop")
        print(f"  ratio {result['rate'] * result['reference']:.0f}x; largest difference: peak "
              f"load {result['peak']:.1e}, max stroke {result['stroke']:.1e}")
    print("target: >= 500 drops/s and >= 50x")


if __name__ == "__main__":
    main()
