"""Drop simulation speed: batched fast path vs the scipy reference, at equal accuracy.

Run:  .venv/bin/python benchmarks/bench_simulation.py [--drops N] [--workers W] [--repeats R]

Simulates 2 s records at 1 kHz output of the seed amphibian's main gear (drop heights
spread over 200-300 mm) with the batched RK4 path, split over W processes, and times
the scipy LSODA reference on a few drops.  Prints drops per second, the speed ratio and
the largest difference in peak load and maximum stroke between the two paths.
Target (issue 3): >= 500 drops/s and >= 50x.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from test_drop_model import seed_gear  # noqa: E402  (the seed gear's parameter set)

from certkit.simulation import simulate_batch, simulate_reference  # noqa: E402

G = 9.80665


def _batch(velocities: np.ndarray):
    drops = simulate_batch(seed_gear(), velocities, duration=2.0)
    return drops.load.max(axis=1), drops.stroke.max(axis=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--drops", type=int, default=4096)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--reference-drops", type=int, default=5)
    args = parser.parse_args()
    velocities = np.sqrt(2 * G * np.linspace(0.2, 0.3, args.drops))
    chunks = np.array_split(velocities, args.workers)
    rates = []
    with ProcessPoolExecutor(args.workers) as pool:
        for _ in range(args.repeats):
            start = time.perf_counter()
            results = list(pool.map(_batch, chunks))
            elapsed = time.perf_counter() - start
            rates.append(args.drops / elapsed)
            print(f"batch of {args.drops} drops on {args.workers} workers: {elapsed:.2f} s, "
                  f"{rates[-1]:.0f} drops/s")
    peaks = np.concatenate([r[0] for r in results])
    strokes = np.concatenate([r[1] for r in results])
    reference_times, peak_error, stroke_error = [], 0.0, 0.0
    for index in np.linspace(0, args.drops - 1, args.reference_drops).astype(int):
        start = time.perf_counter()
        reference = simulate_reference(seed_gear(), float(velocities[index]), lead=0.0)
        reference_times.append(time.perf_counter() - start)
        peak_error = max(peak_error, abs(peaks[index] / reference.load.max() - 1))
        stroke_error = max(stroke_error, abs(strokes[index] / reference.stroke.max() - 1))
    per_drop = statistics.median(reference_times)
    fast = statistics.median(rates)
    print(f"reference (scipy LSODA, rtol 1e-9): median {per_drop:.3f} s per drop")
    print(f"fast path: median {fast:.0f} drops/s; ratio to the reference {fast * per_drop:.0f}x; "
          f"largest difference: peak load {peak_error:.2e}, max stroke {stroke_error:.2e} "
          f"(target >= 500 drops/s and >= 50x)")


if __name__ == "__main__":
    main()
