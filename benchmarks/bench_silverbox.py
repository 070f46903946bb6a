"""Silverbox: fixed-size LS-SVM NARX, identification cost and free-run RMSE on the test sets.

Run:  .venv/bin/python benchmarks/bench_silverbox.py [--data FOLDER] [--repeats 3] [--tune]

Data: SNLS80mV.csv of the Silverbox benchmark (columns V1 = u, V2 = y, volts), read from
``--data``: the folder that holds it or the file itself (default ../shared/data/silverbox
beside the repository; the data are never copied into the repository).  Official split
(identification.md §0, as in the nonlinear_benchmarks loader): training = multisine
samples [40650:105712] (65 062); tests = arrow full [100:40575] (its first 32 000
samples: arrow without extrapolation) and multisine test [105712:127400]; every test is
a free-run simulation from a 50-sample initialisation window of measured outputs, RMSE
over the samples after it.

Model: ``NARX(na=10, nb=10, delay=0, engine="fixed-size", prototypes=500)``.  Choices
made on the training part only, by the free-run RMSE on a validation stretch at its end
(model fitted on the samples before it):
* orders (exploratory runs, validation = training samples 48 000 on, σ² = 800,
  γ = 1e5): delay 0 (u_t enters) 0.23 mV against 0.47 mV with delay 1 (na = nb = 10);
  na = nb = 6 with delay 1 was unstable in free run; 8, 10 and 12 lags with delay 0
  gave 0.22-0.25 mV;
* prototypes (validation = last quarter, tuned γ, σ²): 500 → 0.218 mV, 1 000 → 0.214
  mV, 2 000 → 0.214 mV; 500 kept (fastest);
* (γ, σ²): ``--tune`` reruns :func:`certkit.ident.lssvm.tune` (4 x 4 log grid, Nelder-Mead)
  with the last quarter [89447:105712] as validation and prints the result; the
  constants below are its output.
The test sets take no part in any choice.  Identification = prototype selection and the
primal solve on all 65 062 training samples (median wall time of ``--repeats`` runs;
peak memory of one extra run under tracemalloc, plus the process peak RSS), with BLAS
pinned to one thread (blas_threads.py).  Target: ≤ 30 s and ≤ 2 GB on the 2-core
machine.
"""

from __future__ import annotations

import blas_threads  # first: pins the BLAS threads before numpy is loaded

# isort: split
import argparse
import hashlib
import os
import resource
import statistics
import time
import tracemalloc
from pathlib import Path

import numpy as np

from certkit.ident.lssvm import tune
from certkit.ident.narx import NARX
from certkit.ident.validation import rmse

REPO = Path(__file__).resolve().parent.parent
DATA = REPO.parent / "shared" / "data" / "silverbox"
FILE_NAME = "SNLS80mV.csv"
SHA256 = "ae62d5a91230c10f76e6dd02c8a4fac3c9d4d8a95fbf50e87cb0c4885003e0f1"

TRAIN = slice(40650, 105712)
TESTS = {"multisine": slice(105712, 127400), "arrow full": slice(100, 40575),
         "arrow no-extrapolation": slice(100, 100 + 32000)}
N_INIT = 50
VALIDATION_START = 48797          # within TRAIN: first 3/4 estimation, last 1/4 validation

ORDERS = {"na": 10, "nb": 10, "delay": 0}
PROTOTYPES = 500
GAMMA, SIGMA2 = 1.778e5, 1.581e3  # printed by --tune (31 fits, validation 0.218 mV)

# Free-run simulation RMSE on the test parts [mV], identification.md §4.1: Champneys,
# Beintema, Tóth, Schoukens, Rogers, "Baseline Results for Selected Nonlinear System
# Identification Benchmarks", IFAC-PapersOnLine 58(15) (2024) 474-479, and §4.2.
PUBLISHED = [
    ("LTI ARX (Champneys et al. 2024)", 6.95, 14.2, 6.59),
    ("polynomial NARX (Champneys et al. 2024)", 0.640, 2.25, 0.571),
    ("GP NARX, SE kernel (Champneys et al. 2024)", 0.301, 0.60, 0.259),
    ("MLP NARX (Champneys et al. 2024)", 2.80, 5.18, 2.40),
    ("DT SUBNET (Beintema et al. 2021)", 0.36, 1.4, 0.32),
    ("PNLSS (Paduart 2010; arrow only)", None, 0.26, None),
]


def data_file(path: Path) -> Path | None:
    """The Silverbox CSV: FILE_NAME in the folder ``path``, or ``path`` itself; None if
    there is no such file."""
    file = path / FILE_NAME if path.is_dir() else path
    return file if file.is_file() else None


def load(path: Path) -> tuple[np.ndarray, np.ndarray]:
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    data = np.loadtxt(path, delimiter=",", skiprows=1, usecols=(0, 1))
    print(f"data: {path}  sha256 {'matches' if digest == SHA256 else 'DIFFERS: ' + digest}")
    return data[:, 0], data[:, 1]


def model(gamma: float, sigma2: float) -> NARX:
    return NARX(**ORDERS, gamma=gamma, sigma2=sigma2, engine="fixed-size",
                prototypes=PROTOTYPES)


def tune_on_validation(u: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(γ, σ²) minimising the free-run validation RMSE; training part only."""
    fit_u, fit_y = u[:VALIDATION_START], y[:VALIDATION_START]
    val_u, val_y = u[VALIDATION_START:], y[VALIDATION_START:]

    def cost(gamma: float, sigma2: float) -> float:
        simulated = model(gamma, sigma2).fit(fit_u, fit_y).simulate(val_u, val_y[:N_INIT])
        value = rmse(val_y[N_INIT:], simulated[N_INIT:])
        print(f"  gamma {gamma:9.3g}  sigma2 {sigma2:9.3g}  validation {1e3 * value:8.3f} mV",
              flush=True)
        return value

    start = time.perf_counter()
    result = tune(cost, gamma=(1e2, 1e8), sigma2=(50.0, 5000.0), grid=4, max_refine=20)
    print(f"tuned in {time.perf_counter() - start:.0f} s ({len(result.evaluations)} fits): "
          f"gamma {result.gamma:.4g}, sigma2 {result.sigma2:.4g}, "
          f"validation free-run RMSE {1e3 * result.cost:.3f} mV")
    return result.gamma, result.sigma2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=DATA, metavar="FOLDER",
                        help=f"the folder holding {FILE_NAME}, or the file (default {DATA})")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--tune", action="store_true",
                        help="re-tune (gamma, sigma2) on the validation quarter first")
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error(f"--repeats: expected a whole number >= 1, found {args.repeats}")
    file = data_file(args.data)
    if file is None:
        parser.error(f"--data {args.data}: expected the Silverbox data folder holding "
                     f"{FILE_NAME} (or that file), found no such file")
    u, y = load(file)
    print("load average at start (1, 5, 15 min): "
          + ", ".join(f"{v:.1f}" for v in os.getloadavg()) + f" on {os.cpu_count()} cores; "
          f"thread pools: {blas_threads.loaded_pools()}")
    u_train, y_train = u[TRAIN], y[TRAIN]
    gamma, sigma2 = tune_on_validation(u_train, y_train) if args.tune else (GAMMA, SIGMA2)
    print(f"model: NARX na={ORDERS['na']} nb={ORDERS['nb']} delay={ORDERS['delay']}, "
          f"fixed-size LS-SVM, {PROTOTYPES} prototypes (Renyi entropy, seed 0), "
          f"gamma={gamma:.4g}, sigma2={sigma2:.4g} (standardised regressors)")

    seconds = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        narx = model(gamma, sigma2).fit(u_train, y_train)
        seconds.append(time.perf_counter() - start)
    tracemalloc.start()
    model(gamma, sigma2).fit(u_train, y_train)
    traced_peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    rss_peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024   # Linux: kB
    print(f"identification on {y_train.size} samples ({narx.n_rows_} regression rows): "
          f"median {statistics.median(seconds):.1f} s of "
          f"{', '.join(f'{s:.1f}' for s in seconds)} s; peak memory {traced_peak / 2**20:.0f} MB "
          f"(tracemalloc), process peak RSS {rss_peak / 2**20:.0f} MB  [target <= 30 s, <= 2 GB]")

    ours = {}
    print("\nfree-run simulation RMSE after the 50-sample window (one-step-ahead in brackets):")
    for name, part in TESTS.items():
        start = time.perf_counter()
        simulated = narx.simulate(u[part], y[part][:N_INIT])
        elapsed = time.perf_counter() - start
        one_step = narx.predict(u[part], y[part])
        ours[name] = 1e3 * rmse(y[part][N_INIT:], simulated[N_INIT:])
        print(f"  {name:24s} {ours[name]:7.3f} mV   "
              f"(one-step {1e3 * rmse(y[part][N_INIT:], one_step[N_INIT:]):.3f} mV; "
              f"simulation {elapsed:.1f} s)")

    print("\n{:48s} {:>10s} {:>10s} {:>10s}".format(
        "free-run RMSE [mV]", "multisine", "arrow", "arrow n-e"))

    def cell(value):
        return f"{value:10.3f}" if value is not None else f"{'-':>10s}"

    print(f"{'this run: FS-LSSVM NARX':48s} {cell(ours['multisine'])} "
          f"{cell(ours['arrow full'])} {cell(ours['arrow no-extrapolation'])}")
    for label, multisine, arrow, no_extrapolation in PUBLISHED:
        print(f"{label:48s} {cell(multisine)} {cell(arrow)} {cell(no_extrapolation)}")
    print("published figures: identification.md §4.1 (Champneys et al., IFAC-PapersOnLine "
          "58(15) 2024, doi 10.1016/j.ifacol.2024.08.574) and §4.2")


if __name__ == "__main__":
    main()
