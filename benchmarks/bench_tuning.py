"""The default free-run tuning search of certkit.ident on a 5 000-sample record: how long it
takes, what it chooses and the chosen model's free-run error on a separate record.

Run (from the repository root):

    .venv/bin/python benchmarks/bench_tuning.py [--repeats 3] [--engine fixed-size|full] [--jobs 2]
                                                [--no-sysidentpy]

SysIdentPy 0.9 is optional and never a certkit dependency (its wheel pins numpy <= 2.3.5):
``pip install --target /tmp/sip sysidentpy==0.9 --no-deps`` and PYTHONPATH=/tmp/sip; without
it its row is skipped with a message.

Data (made here, seeded, nothing read from disk): a hysteretic damper, the Bouc–Wen model
(Wen 1976) of a mass on a spring and a hysteretic element,

    m·ẍ + c·ẋ + k·x + z = F(t),   ż = A·ẋ − β·|ẋ|·|z|^(n−1)·z − γ·ẋ·|z|^n,

with m = 2 kg, c = 10 N·s/m, k = 5·10⁴ N/m, A = 5·10⁴ N/m, β = 1·10³ m⁻¹, γ = 8·10² m⁻¹,
n = 2 (the parameters of the Bouc–Wen benchmark of Noël & Schoukens 2016, scaled), driven
by a random-phase multisine force of 5–150 Hz (RMS 50 N), sampled at 750 Hz (integrated
with 20 RK4 sub-steps per sample), output the displacement with 1 % noise.  Estimation:
5 000 samples; validation: another 2 000 samples from another multisine realisation.

Search: ``tune_free_run(NARX(engine=...), u, y, orders={"na": [1, 2, 3], "nb": [1, 2, 3]})``
with every other setting at its default (FreeRunCV with 8 blocked folds, 5 x 5 log grid of
(γ, σ²) and the Nelder–Mead refinement per order pair): about 360 candidates x 8 folds.
Target (issue 29): ≤ 60 s on 2 quiet cores.  BLAS pinned to one thread.

SysIdentPy 0.9 beside it (skip with ``--no-sysidentpy``): FROLS polynomial NARX, AIC term
selection over 20 terms, its degree ∈ {2, 3} and (ylag, xlag) ∈ {1, 2, 3}² chosen, like
certkit's orders, by 8 blocked free-run folds of the estimation record only
(``FreeRunCV(n_init=3)``: every candidate scored on the same samples; SysIdentPy fits one
record, so a fold's training blocks are concatenated), in this process (no workers).  The
table compares both on the validation record in free run from its first 3 measured
outputs (the largest lag window of either search), RMSE over the samples after them.

References: Y.K. Wen, "Method for random vibration of hysteretic systems", J. Eng. Mech.
Div. 102 (1976) 249-263; J.P. Noël, M. Schoukens, "Hysteretic benchmark with a dynamic
nonlinearity", Workshop on Nonlinear System Identification Benchmarks, 2016.
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import time

import blas_threads  # noqa: F401  (first: pins the BLAS threads before numpy loads)
import numpy as np

from certkit.ident import NARX, FreeRunCV, rmse, tune_free_run
from frols import INSTALL_HINT, FROLSNARX

RATE = 750.0
SUBSTEPS = 20
M, C, K = 2.0, 10.0, 5e4
A, BETA, GAMMA, N = 5e4, 1e3, 8e2, 2.0
N_INIT = 3                      # the table's free runs start from 3 measured outputs
FROLS_DEGREES, FROLS_LAGS = (2, 3), (1, 2, 3)


def multisine(samples: int, seed: int) -> np.ndarray:
    """A random-phase multisine of 5–150 Hz with RMS 50 N (one period over the record)."""
    rng = np.random.default_rng(seed)
    t = np.arange(samples) / RATE
    lines = np.arange(1, samples // 2)
    f = lines * RATE / samples
    lines, f = lines[(f >= 5) & (f <= 150)], f[(f >= 5) & (f <= 150)]
    phases = rng.uniform(0, 2 * np.pi, lines.size)
    u = np.sin(2 * np.pi * f[None, :] * t[:, None] + phases[None, :]).sum(axis=1)
    return 50.0 * u / np.std(u)


def damper(force: np.ndarray, seed: int) -> np.ndarray:
    """Displacement of the Bouc–Wen damper under ``force`` (zero-order hold), with 1 % noise."""
    def rates(state, f):
        x, v, z = state
        dz = A * v - BETA * abs(v) * abs(z) ** (N - 1) * z - GAMMA * v * abs(z) ** N
        return np.array([v, (f - C * v - K * x - z) / M, dz])

    h = 1.0 / (RATE * SUBSTEPS)
    state = np.zeros(3)
    out = np.empty(force.size)
    for i, f in enumerate(force):
        out[i] = state[0]
        for _ in range(SUBSTEPS):
            k1 = rates(state, f)
            k2 = rates(state + 0.5 * h * k1, f)
            k3 = rates(state + 0.5 * h * k2, f)
            k4 = rates(state + h * k3, f)
            state = state + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    rng = np.random.default_rng(seed + 1000)
    return out + 0.01 * np.std(out) * rng.standard_normal(out.size)


def validation_error(model, u_val, y_val) -> float:
    """Free-run RMSE on the validation record from its first N_INIT measured outputs [mm]."""
    simulated = model.simulate(u_val, y_val[:N_INIT])
    return rmse(y_val[N_INIT:], simulated[N_INIT:])


def sysidentpy_row(u_est, y_est, u_val, y_val):
    """SysIdentPy's FROLS NARX, its degree and lags chosen by blocked free-run folds of the
    estimation record: (label, validation RMSE, tuning s, fit s), or None when SysIdentPy
    is not installed."""
    try:
        import sysidentpy
    except ImportError:
        print(f"\nSysIdentPy is not installed: its row is skipped ({INSTALL_HINT})")
        return None
    print(f"\nSysIdentPy {getattr(sysidentpy, '__version__', '?')}: FROLS polynomial NARX, "
          f"AIC; degree and (ylag, xlag) by 8 blocked free-run folds (estimation record only)",
          flush=True)
    start = time.perf_counter()
    cost = FreeRunCV(n_init=N_INIT)
    pairs = [(u_est[:, None], y_est)]
    scores = {}
    for degree, ylag, xlag in itertools.product(FROLS_DEGREES, FROLS_LAGS, FROLS_LAGS):
        scores[(degree, ylag, xlag)] = cost(FROLSNARX(ylag, xlag, degree=degree), pairs)
        print(f"  degree {degree} ylag {ylag} xlag {xlag}: free-run CV RMSE "
              f"{math.sqrt(scores[(degree, ylag, xlag)] * np.var(y_est)):.4f} mm", flush=True)
    degree, ylag, xlag = min(scores, key=scores.get)
    tuning = time.perf_counter() - start
    start = time.perf_counter()
    model = FROLSNARX(ylag, xlag, degree=degree).fit(u_est, y_est)
    fit = time.perf_counter() - start
    label = (f"SysIdentPy 0.9 FROLS, degree {degree}, ylag {ylag} xlag {xlag} "
             f"({len(model.model_.final_model)} terms)")
    return label, validation_error(model, u_val, y_val), tuning, fit


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=1, metavar="N")
    parser.add_argument("--engine", choices=("fixed-size", "full"), default="fixed-size")
    parser.add_argument("--jobs", type=int, default=1, metavar="N",
                        help="worker processes scoring the folds (tune_free_run's n_jobs)")
    parser.add_argument("--no-sysidentpy", action="store_true", help="skip SysIdentPy")
    args = parser.parse_args()
    u_est, u_val = multisine(5000, 1), multisine(2000, 2)
    y_est, y_val = damper(u_est, 1), damper(u_val, 2)
    scale = 1e3                                          # mm
    print(f"data: Bouc-Wen damper, estimation 5000 samples, validation 2000 samples, "
          f"output RMS {scale * np.std(y_est):.3f} mm", flush=True)
    seconds = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        model, surface = tune_free_run(NARX(na=2, nb=2, engine=args.engine), u_est,
                                       scale * y_est, orders={"na": [1, 2, 3],
                                                              "nb": [1, 2, 3]},
                                       n_jobs=args.jobs)
        seconds.append(time.perf_counter() - start)
    simulated = model.simulate(u_val, scale * y_val[:model.init_length])
    error = rmse(scale * y_val[model.init_length:], simulated[model.init_length:])
    print(f"default search, engine {args.engine}, {args.jobs} worker process(es): "
          f"{len(surface.rows)} candidates; "
          f"median {statistics.median(seconds):.1f} s over {len(seconds)} run(s) "
          f"({', '.join(f'{s:.1f}' for s in seconds)}) [target <= 60 s]")
    chosen = {k: getattr(model, k) for k in ("na", "nb", "gamma", "sigma2")}
    print(f"chosen {chosen}; validation free-run RMSE {error:.4f} mm "
          f"({100 * error / (scale * np.std(y_val)):.1f} % of the output RMS)")
    start = time.perf_counter()
    model.fit(u_est, scale * y_est)                      # refitted once more, timed
    fit = time.perf_counter() - start
    rows = [(f"certkit NARX ({args.engine} LS-SVM), na {model.na} nb {model.nb}",
             validation_error(model, u_val, scale * y_val), statistics.median(seconds), fit)]
    if not args.no_sysidentpy:
        row = sysidentpy_row(u_est, scale * y_est, u_val, scale * y_val)
        if row is not None:
            rows.append(row)

    print(f"\n{'validation free run from ' + str(N_INIT) + ' measured outputs':60s} "
          f"{'RMSE [mm]':>9s} {'% RMS':>6s} {'tuning [s]':>10s} {'fit [s]':>8s}")
    for label, value, tuning, fit in rows:
        print(f"{label:60s} {value:9.4f} {100 * value / (scale * np.std(y_val)):6.1f} "
              f"{tuning:10.1f} {fit:8.2f}")
    print(f"tuning: certkit's default search in {args.jobs} worker process(es) (median of "
          f"{len(seconds)})" + (f"; SysIdentPy's {len(FROLS_DEGREES) * len(FROLS_LAGS) ** 2} "
                                f"candidates x 8 folds in this process" if len(rows) > 1
                                else ""))


if __name__ == "__main__":
    main()
