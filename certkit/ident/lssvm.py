"""LS-SVM regression and the tuning of its hyper-parameters.

A kernel expansion ``ŷ(x) = Σ_j α_j K(x, c_j) + b`` with the RBF kernel of LS-SVMlab,
K(x, z) = exp(−‖x − z‖²/σ²) — no factor 2, so (γ, σ²) from LS-SVMlab papers transfer
unchanged (Suykens, Van Gestel, De Brabanter, De Moor & Vandewalle, *Least Squares Support
Vector Machines*, World Scientific, 2002).  The estimators follow the scikit-learn pattern:
hyper-parameters in the constructor, ``fit`` returns ``self``, learned attributes end in ``_``.

* :class:`LSSVMRegressor` — the dual LS-SVM (one Cholesky factorisation, N ≲ 5 000).
* :func:`tune` — (γ, σ²) by a log grid and a Nelder–Mead refinement of any cost
  callable; :func:`kfold_cost` is the plain cross-validation cost.

The fixed-size LS-SVM is in :mod:`certkit.ident.fixed_size`, the NARX model in
:mod:`certkit.ident.narx`, the error measures in :mod:`certkit.ident.validation`.
Numpy and scipy only.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
from scipy import linalg, optimize

from certkit.ident.reuse import digest, kept, reusing
from certkit.ident.experiments import DataInputError, positive_number, signal
from certkit.ident.search_space import SearchEdge, range_edges
from certkit.ident.signature import orders_positional
from certkit.ident.sizing import check_dense_memory

CHUNK_ENTRIES = 4_000_000      # kernel entries evaluated at once (≈ 32 MB) in predictions



def squared_distances(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """D[i, j] = ‖x_i − z_j‖² (at least 0) for rows x_i of ``x`` (n, d) and z_j of ``z``."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    z = np.atleast_2d(np.asarray(z, dtype=float))
    # (‖x_i‖² + ‖z_j‖²) − 2·x_i·z_j, with one (n, m) array more than the result, not four
    squared = np.sum(x * x, axis=1)[:, None] + np.sum(z * z, axis=1)[None, :]
    np.subtract(squared, 2.0 * x @ z.T, out=squared)
    return np.maximum(squared, 0.0, out=squared)


def training_distances(x: np.ndarray) -> np.ndarray:
    """:func:`squared_distances` of the rows of ``x`` to each other, exactly symmetric (the
    lower triangle mirrored): rounding can leave D[i, j] and D[j, i] a bit apart."""
    distances = squared_distances(x, x)
    for i in range(distances.shape[0] - 1):
        distances[i, i + 1:] = distances[i + 1:, i]
    return distances


def rbf_kernel(x: np.ndarray, z: np.ndarray, sigma2: float) -> np.ndarray:
    """K[i, j] = exp(−‖x_i − z_j‖²/σ²) for rows x_i of ``x`` (n, d) and z_j of ``z`` (m, d)."""
    kernel = squared_distances(x, z)
    np.divide(kernel, -sigma2, out=kernel)          # −D/σ², the same numbers as (−D)/σ²
    return np.exp(kernel, out=kernel)



# ----------------------------------------------------------------------------- checks
def feature_matrix(name: str, x) -> np.ndarray:
    """Inputs as an (n, d) float array: 1-D means n samples of one feature."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or x.shape[0] == 0 or x.shape[1] == 0:
        raise DataInputError(name, f"expected a non-empty (n_samples, n_features) array, "
                                   f"found shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise DataInputError(name, "expected finite values, found NaN or infinite values")
    return x




def kept_kernel(x: np.ndarray, z: np.ndarray, sigma2: float) -> np.ndarray:
    """:func:`rbf_kernel`, kept inside a tuning search (:mod:`certkit.ident.reuse`) under the
    rows' bytes and σ²: the fits of one fold predict the same rows from the same centres
    (its training rows) for every γ.  Not to be modified."""
    return kept("kernel", digest(x, z, sigma2), lambda: rbf_kernel(x, z, sigma2))


def kernel_expansion(x: np.ndarray, centres: np.ndarray, coef: np.ndarray, bias: float,
                      sigma2: float) -> np.ndarray:
    """Σ_j coef_j K(x, c_j) + bias, in row chunks so memory stays bounded."""
    rows = max(1, CHUNK_ENTRIES // max(1, centres.shape[0]))
    out = np.empty(x.shape[0])
    for start in range(0, x.shape[0], rows):
        out[start:start + rows] = kept_kernel(x[start:start + rows], centres, sigma2) @ coef
    return out + bias



class KernelModel:
    """Shared predict of the kernel-expansion estimators."""

    def predict(self, X) -> np.ndarray:
        """Model output ŷ(x) = Σ_j α_j K(x, c_j) + b for the rows of ``X`` (plus βᵀx + θᵀc(x)
        for a partially linear :class:`~certkit.ident.fixed_size.FixedSizeLSSVM`).

        Parameters
        ----------
        X : array_like, shape (n, d) or (n,)
            Points to evaluate, in the units used for ``fit``.

        Returns
        -------
        numpy.ndarray, shape (n,)
        """
        if not hasattr(self, "alpha_"):
            raise ValueError(f"{type(self).__name__} is not fitted: call fit(X, y) first")
        X = feature_matrix("X", X)
        if X.shape[1] != self.support_.shape[1]:
            raise ValueError(f"X has {X.shape[1]} features, the model was fitted with "
                             f"{self.support_.shape[1]}")
        return self._predict_rows(X)

    def _predict_rows(self, X: np.ndarray) -> np.ndarray:
        """The model on checked rows (a model with more terms adds them here)."""
        return kernel_expansion(X, self.support_, self.alpha_, self.b_, self.sigma2)



# ----------------------------------------------------------------------------- LS-SVM
class LSSVMRegressor(KernelModel):
    """Least-squares support vector machine regression (dual form, RBF kernel).

    Parameters
    ----------
    gamma : float
        Regularisation constant γ > 0 (weight of the squared errors) [-].
    sigma2 : float
        RBF bandwidth σ² > 0 in K(x, z) = exp(−‖x − z‖²/σ²) [units of x, squared].
    bias : bool, default True
        Fit the bias b.  ``False`` drops b and the constraint Σα = 0: the model is then
        kernel ridge regression with ridge 1/γ.

    Attributes
    ----------
    alpha_ : numpy.ndarray, shape (N,)
        Dual coefficients (support values) α.
    b_ : float
        Bias b.
    support_ : numpy.ndarray, shape (N, d)
        The training inputs (every training point is a support vector).

    Notes
    -----
    Primal: min ½‖w‖² + (γ/2) Σ e_k² subject to y_k = wᵀφ(x_k) + b + e_k.  Its optimality
    conditions are the dual linear system (Suykens et al. 2002, ch. 3)::

        [ 0   1ᵀ          ] [ b ]   [ 0 ]
        [ 1   Ω + I/γ     ] [ α ] = [ y ],     Ω_kl = K(x_k, x_l).

    H = Ω + I/γ is symmetric positive definite, so with one Cholesky factor of H the
    block elimination (Schur complement 1ᵀH⁻¹1 of the bias) gives, without any inverse,

        b = 1ᵀH⁻¹y / 1ᵀH⁻¹1,    α = H⁻¹(y − b·1).

    Cost O(N³) time and O(N²) memory: use :class:`FixedSizeLSSVM` beyond a few thousand
    samples.  ``fit`` refuses N whose kernel matrix would exceed
    :data:`certkit.ident.sizing.MEMORY_BUDGET` (:func:`~certkit.ident.sizing.dense_bytes`).

    References
    ----------
    J.A.K. Suykens, T. Van Gestel, J. De Brabanter, B. De Moor, J. Vandewalle,
    *Least Squares Support Vector Machines*, World Scientific, 2002, ch. 3.
    """

    @orders_positional()
    def __init__(self, *, gamma: float = 1.0, sigma2: float = 1.0, bias: bool = True):
        self.gamma = gamma
        self.sigma2 = sigma2
        self.bias = bias

    def fit(self, X, y) -> LSSVMRegressor:
        """Solve the dual system for α and b.

        Parameters
        ----------
        X : array_like, shape (N, d) or (N,)
            Training inputs.
        y : array_like, shape (N,)
            Training targets.

        Returns
        -------
        self
        """
        gamma = positive_number("gamma", self.gamma)
        sigma2 = positive_number("sigma2", self.sigma2)
        X = feature_matrix("X", X)
        y = signal("y", y, X.shape[0])
        check_dense_memory("LSSVMRegressor", X.shape[0], "FixedSizeLSSVM(gamma=…, sigma2=…, "
                                                         "prototypes=…) (memory O(N·M), any N)")
        # the training rows' distances do not depend on (γ, σ²): a tuning grid computes
        # them once (certkit.ident.reuse)
        distances = kept("squared distances", digest(X), lambda: training_distances(X))
        H = np.divide(distances, -sigma2)                     # Ω = exp(−D/σ²)
        np.exp(H, out=H)
        H[np.diag_indices_from(H)] += 1.0 / gamma
        # H is exactly symmetric, so H.T is H in LAPACK's column-major order: factorised in
        # place, without the transposing copy a row-major array costs (a third of the time)
        factor = linalg.cho_factor(H.T, lower=True, overwrite_a=True, check_finite=False)
        if self.bias:
            nu, eta = linalg.cho_solve(factor, np.column_stack([y, np.ones_like(y)]),
                                       check_finite=False).T          # H⁻¹y, H⁻¹1
            b = float(nu.sum() / eta.sum())
            self.alpha_ = nu - b * eta
        else:
            b = 0.0
            self.alpha_ = linalg.cho_solve(factor, y, check_finite=False)
        self.b_ = b
        self.support_ = X.copy()
        return self



# ----------------------------------------------------------------------------- tuning
@contextmanager
def recorded_warnings():
    """Record the warnings raised inside the block instead of showing them.

    Yields a list that holds, once the block has ended (normally or by an exception), each
    warning as "Category: message", once each, in the order first raised: what a rejected
    tuning candidate raised (an overflow in a diverging free run, an ill-conditioned
    matrix) belongs in its record, not on the user's screen.
    """
    messages: list[str] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield messages
        finally:
            messages.extend(dict.fromkeys(f"{w.category.__name__}: {w.message}"
                                          for w in caught))


@dataclass(frozen=True)
class TuningResult:
    """Outcome of :func:`tune`: the best point and every evaluation made.

    ``evaluations``: (γ, σ², cost) in call order; ``warnings``: for each evaluation, the
    warnings its cost raised (:func:`recorded_warnings`: recorded, not shown); ``edges``:
    the ends of the ranges the best point lies on
    (:func:`certkit.ident.search_space.range_edges`).
    """

    gamma: float
    sigma2: float
    cost: float
    evaluations: tuple[tuple[float, float, float], ...]
    warnings: tuple[tuple[str, ...], ...] = ()
    edges: tuple[SearchEdge, ...] = ()



def tune(cost: Callable[[float, float], float], *, gamma=(1e-2, 1e6),
         sigma2=(1e-2, 1e3), grid: int | tuple[int, int] = 7,
         start: tuple[float, float] | None = None,
         refine: bool = True, max_refine: int = 40,
         tolerance: float = 0.02, allow_infinite: bool = False,
         prefetch: Callable[[list[tuple[float, float]]], None] | None = None
         ) -> TuningResult:
    """Minimise a cross-validation cost over (γ, σ²): log grid, then Nelder–Mead.

    Parameters
    ----------
    cost : callable
        ``cost(gamma, sigma2) -> float``, smaller is better; e.g. :func:`kfold_cost` or
        :meth:`NARX.simulation_cost` (free-run simulation error).  Non-finite values are
        treated as +inf.
    gamma, sigma2 : (low, high) or float
        Search range (searched in log10), or a number to keep that parameter fixed.
    grid : int or (int, int)
        Grid points per searched parameter, evenly spaced in log10 (grid ≥ 2); a pair
        gives (γ points, σ² points).
    start : (gamma, sigma2), optional
        Skip the grid and refine from this point (must lie in the ranges).
    refine : bool
        Run the Nelder–Mead refinement (log10 space, within the ranges).
    max_refine : int
        Cost evaluations allowed to the refinement.
    tolerance : float
        Simplex size [decades] at which the refinement stops.
    allow_infinite : bool
        Return a result of cost +inf when no evaluation is finite, instead of raising
        (a caller that searches several structures and ranks them itself).
    prefetch : callable, optional
        Called once with the grid's (γ, σ²) points, in the order they are then evaluated,
        before the first: a cost that scores in worker processes starts them all at once
        (:func:`certkit.ident.tune_free_run`).

    Returns
    -------
    TuningResult
        Best (γ, σ², cost) over the grid and the refinement, every evaluation with the
        warnings it raised (recorded, not shown), and the ends of the ranges the best lies
        on (no warning here: the caller that chose the ranges says so).

    Notes
    -----
    Deterministic: no random numbers; the same cost gives the same result.  The grid
    gives a global view (as LS-SVMlab's ``tunelssvm`` does with coupled simulated
    annealing), the simplex polishes the best grid point; the first simplex step is one
    grid spacing.  The fits of one search share what does not depend on γ (or on σ²):
    :mod:`certkit.ident.reuse`.
    """
    with reusing():
        return _tune(cost, gamma, sigma2, grid, start, refine, max_refine, tolerance,
                     allow_infinite, prefetch)


def _tune(cost, gamma, sigma2, grid, start, refine, max_refine, tolerance,
          allow_infinite, prefetch) -> TuningResult:
    names = ("gamma", "sigma2")
    specs = (gamma, sigma2)
    fixed, bounds = {}, {}
    for name, spec in zip(names, specs):
        if np.ndim(spec) == 0:
            fixed[name] = positive_number(name, spec)
        else:
            low, high = (positive_number(name, v) for v in spec)
            if not low < high:
                raise ValueError(f"{name} range must be (low, high) with low < high")
            bounds[name] = (math.log10(low), math.log10(high))
    free = list(bounds)
    points = dict(zip(names, (grid, grid) if np.ndim(grid) == 0 else tuple(grid)))
    record: dict[tuple, float] = {}
    order: list[tuple[float, float, float]] = []
    raised: list[tuple[str, ...]] = []

    def point(logs) -> dict:
        values = dict(fixed)
        values.update({n: 10.0 ** float(v) for n, v in zip(free, logs)})
        return values

    def rounded(logs) -> tuple:
        return tuple(round(float(v), 9) for v in logs)

    def evaluate(logs) -> float:
        key = rounded(logs)
        if key not in record:
            values = point(key)
            with recorded_warnings() as messages:
                value = float(cost(values["gamma"], values["sigma2"]))
            record[key] = value if math.isfinite(value) else math.inf
            order.append((values["gamma"], values["sigma2"], record[key]))
            raised.append(tuple(messages))
        return record[key]

    if not free:
        evaluate(())
        refine = False
    elif start is None:
        if min(points[n] for n in free) < 2:
            raise ValueError("grid must be at least 2")
        axes = [np.linspace(*bounds[n], points[n]) for n in free]
        grid_logs = np.array(np.meshgrid(*axes, indexing="ij")).reshape(len(free), -1).T
        if prefetch is not None:
            prefetch([(v["gamma"], v["sigma2"]) for v in map(point, map(rounded, grid_logs))])
        for logs in grid_logs:
            evaluate(logs)
    else:
        start_values = dict(zip(names, start))
        logs = []
        for n in free:
            value = math.log10(positive_number(n, start_values[n]))
            low, high = bounds[n]
            if not low - 1e-9 <= value <= high + 1e-9:
                raise ValueError(f"start {n}={start_values[n]} lies outside its range")
            logs.append(min(max(value, low), high))   # a grid end point, up to rounding
        evaluate(logs)

    if refine:
        best = min(record, key=record.get)
        low = np.array([bounds[n][0] for n in free])
        high = np.array([bounds[n][1] for n in free])
        x0 = np.clip(np.array(best, dtype=float), low, high)  # rounding can leave a bound
        steps = np.array([(bounds[n][1] - bounds[n][0]) / max(points[n] - 1, 1)
                          for n in free])
        simplex = [x0]
        for i, n in enumerate(free):
            vertex = x0.copy()
            vertex[i] += steps[i] if x0[i] + steps[i] <= bounds[n][1] else -steps[i]
            simplex.append(np.clip(vertex, low, high))
        scale = abs(record[best]) if math.isfinite(record[best]) else 1.0
        optimize.minimize(evaluate, x0, method="Nelder-Mead",
                          bounds=[bounds[n] for n in free],
                          options={"initial_simplex": np.array(simplex),
                                   "xatol": tolerance, "fatol": 1e-4 * scale,
                                   "maxfev": max_refine})

    best = min(record, key=record.get)
    if not math.isfinite(record[best]) and not allow_infinite:
        raise ValueError("the cost was not finite at any evaluated (gamma, sigma2)")
    values = point(best)
    edges = range_edges(values, dict(zip(names, specs)))
    return TuningResult(values["gamma"], values["sigma2"], record[best], tuple(order),
                        tuple(raised), tuple(edges))



def kfold_cost(make_model: Callable[[float, float], object], X, y, *, folds: int = 5,
               loss: Callable[[np.ndarray, np.ndarray], float] | None = None
               ) -> Callable[[float, float], float]:
    """Cross-validation cost on ``folds`` contiguous blocks (deterministic).

    Parameters
    ----------
    make_model : callable
        ``make_model(gamma, sigma2)`` returns an unfitted estimator with fit/predict.
    X, y : array_like
        Data; folds are contiguous blocks in the given order (shuffle beforehand, with
        a seed, if the rows are ordered).
    folds : int
        Number of folds (≥ 2).
    loss : callable, optional
        ``loss(y_true, y_pred)``; default mean squared error.

    Returns
    -------
    callable
        ``cost(gamma, sigma2)``: the held-out loss averaged over the folds.
    """
    X = feature_matrix("X", X)
    y = signal("y", y, X.shape[0])
    if not 2 <= folds <= X.shape[0]:
        raise ValueError(f"folds must be between 2 and the number of samples, got {folds}")
    loss = loss or (lambda t, p: float(np.mean((t - p) ** 2)))
    blocks = np.array_split(np.arange(X.shape[0]), folds)

    def cost(gamma: float, sigma2: float) -> float:
        total = 0.0
        for held in blocks:
            train = np.ones(X.shape[0], dtype=bool)
            train[held] = False
            model = make_model(gamma, sigma2).fit(X[train], y[train])
            total += loss(y[held], model.predict(X[held]))
        return total / folds

    return cost
