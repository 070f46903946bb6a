"""LS-SVM regression, fixed-size LS-SVM and the LS-SVM NARX black-box model.

Everything here is a kernel expansion ``ŷ(x) = Σ_j α_j K(x, c_j) + b`` with the RBF
kernel of LS-SVMlab, K(x, z) = exp(−‖x − z‖²/σ²) — no factor 2, so (γ, σ²) from
LS-SVMlab papers transfer unchanged (identification.md §1).  The estimators follow the
scikit-learn pattern: hyper-parameters in the constructor, ``fit`` returns ``self``,
learned attributes end in ``_``.

* :class:`LSSVMRegressor` — the dual LS-SVM (one Cholesky factorisation, N ≲ 5 000).
* :class:`FixedSizeLSSVM` — Nyström features on M prototypes chosen by quadratic Rényi
  entropy, ridge regression in the primal (memory O(M²), any N).
* :func:`tune` — (γ, σ²) by a log grid and a Nelder–Mead refinement of any cost
  callable; :func:`kfold_cost` is the plain cross-validation cost.
* :class:`NARX` — LS-SVM NARX model; ``predict`` is one-step-ahead, ``simulate`` is the
  free run; automatic tuning uses the free-run simulation error on held-out data.
* Metrics (:func:`rmse`, :func:`nrmse`, :func:`fit_percent`, :func:`max_abs_error`) and
  the residual whiteness tests of :func:`residual_analysis`.

Numpy and scipy only.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import linalg, optimize, special

_CHUNK_ENTRIES = 4_000_000      # kernel entries evaluated at once (≈ 32 MB) in predictions


def rbf_kernel(x: np.ndarray, z: np.ndarray, sigma2: float) -> np.ndarray:
    """K[i, j] = exp(−‖x_i − z_j‖²/σ²) for rows x_i of ``x`` (n, d) and z_j of ``z`` (m, d)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    z = np.atleast_2d(np.asarray(z, dtype=float))
    squared = (np.sum(x * x, axis=1)[:, None] + np.sum(z * z, axis=1)[None, :]
               - 2.0 * x @ z.T)
    return np.exp(-np.maximum(squared, 0.0) / sigma2)


# ----------------------------------------------------------------------------- checks
def _positive(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number, got {value!r}") from None
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return value


def _matrix(name: str, x) -> np.ndarray:
    """Inputs as an (n, d) float array: 1-D means n samples of one feature."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or x.shape[0] == 0 or x.shape[1] == 0:
        raise ValueError(f"{name} must be a non-empty (n_samples, n_features) array, "
                         f"got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return x


def _vector(name: str, y, length: int | None = None) -> np.ndarray:
    y = np.asarray(y, dtype=float)
    if y.ndim != 1 or y.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {y.shape}")
    if length is not None and y.size != length:
        raise ValueError(f"{name} has {y.size} samples, expected {length}")
    if not np.all(np.isfinite(y)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return y


def _kernel_expansion(x: np.ndarray, centres: np.ndarray, coef: np.ndarray, bias: float,
                      sigma2: float) -> np.ndarray:
    """Σ_j coef_j K(x, c_j) + bias, in row chunks so memory stays bounded."""
    rows = max(1, _CHUNK_ENTRIES // max(1, centres.shape[0]))
    out = np.empty(x.shape[0])
    for start in range(0, x.shape[0], rows):
        out[start:start + rows] = rbf_kernel(x[start:start + rows], centres, sigma2) @ coef
    return out + bias


class _KernelModel:
    """Shared predict of the kernel-expansion estimators."""

    def predict(self, X) -> np.ndarray:
        """Model output ŷ(x) = Σ_j α_j K(x, c_j) + b for the rows of ``X``.

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
        X = _matrix("X", X)
        if X.shape[1] != self.support_.shape[1]:
            raise ValueError(f"X has {X.shape[1]} features, the model was fitted with "
                             f"{self.support_.shape[1]}")
        return _kernel_expansion(X, self.support_, self.alpha_, self.b_, self.sigma2)


# ----------------------------------------------------------------------------- LS-SVM
class LSSVMRegressor(_KernelModel):
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
    conditions are the dual linear system (identification.md §1.1)::

        [ 0   1ᵀ          ] [ b ]   [ 0 ]
        [ 1   Ω + I/γ     ] [ α ] = [ y ],     Ω_kl = K(x_k, x_l).

    H = Ω + I/γ is symmetric positive definite, so with one Cholesky factor of H the
    block elimination (Schur complement 1ᵀH⁻¹1 of the bias) gives, without any inverse,

        b = 1ᵀH⁻¹y / 1ᵀH⁻¹1,    α = H⁻¹(y − b·1).

    Cost O(N³) time and O(N²) memory: use :class:`FixedSizeLSSVM` beyond a few thousand
    samples.

    References
    ----------
    J.A.K. Suykens, T. Van Gestel, J. De Brabanter, B. De Moor, J. Vandewalle,
    *Least Squares Support Vector Machines*, World Scientific, 2002, ch. 3.
    """

    def __init__(self, gamma: float = 1.0, sigma2: float = 1.0, *, bias: bool = True):
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
        gamma = _positive("gamma", self.gamma)
        sigma2 = _positive("sigma2", self.sigma2)
        X = _matrix("X", X)
        y = _vector("y", y, X.shape[0])
        H = rbf_kernel(X, X, sigma2)
        H[np.diag_indices_from(H)] += 1.0 / gamma
        factor = linalg.cho_factor(H, lower=True, overwrite_a=True, check_finite=False)
        nu = linalg.cho_solve(factor, y, check_finite=False)                  # H⁻¹y
        if self.bias:
            eta = linalg.cho_solve(factor, np.ones_like(y), check_finite=False)  # H⁻¹1
            b = float(nu.sum() / eta.sum())
            self.alpha_ = nu - b * eta
        else:
            b = 0.0
            self.alpha_ = nu
        self.b_ = b
        self.support_ = X.copy()
        return self


# ------------------------------------------------------------------ fixed-size LS-SVM
def renyi_bandwidth(X) -> float:
    """Default σ² of the entropy criterion: the normal-reference (Silverman) rule.

    h² = s̄²·(4/((d + 2)N))^(2/(d+4)) with s̄² the mean variance of the columns; in the
    kernel convention exp(−‖x − z‖²/σ²) this is σ² = 2h².
    """
    X = _matrix("X", X)
    n, d = X.shape
    spread = float(np.mean(np.var(X, axis=0)))
    if spread == 0.0:
        return 1.0
    return 2.0 * spread * (4.0 / ((d + 2) * n)) ** (2.0 / (d + 4))


def select_prototypes(X, size: int, sigma2: float, *, n_swaps: int | None = None,
                      random_state: int = 0) -> np.ndarray:
    """Indices of ``size`` rows of ``X`` that maximise the quadratic Rényi entropy.

    Parameters
    ----------
    X : array_like, shape (N, d)
        Candidate points.
    size : int
        Number of prototypes M (all rows when M ≥ N).
    sigma2 : float
        Bandwidth of the Parzen kernel in the entropy estimate.
    n_swaps : int, optional
        Number of proposed swaps; default max(2 000, 10·M).
    random_state : int
        Seed: the result is a deterministic function of (X, size, sigma2, n_swaps, seed).

    Returns
    -------
    numpy.ndarray of int, shape (M,)
        Row indices, in the order of the working set.

    Notes
    -----
    Quadratic Rényi entropy of the working set S (Parzen estimate, constants dropped):
    H_R(S) = −log(M⁻² Σ_{i,j∈S} K(x_i, x_j)).  Starting from a random working set, each
    step proposes to replace a random member by a random candidate and keeps the swap
    when H_R increases, i.e. when the kernel sum decreases.  The row sums of the working
    set's kernel matrix are updated in O(M) per step.  Scheme of the fixed-size LS-SVM
    (Suykens et al. 2002, §6.5; De Brabanter et al. 2010).

    References
    ----------
    K. De Brabanter, J. De Brabanter, J.A.K. Suykens, B. De Moor, "Optimized fixed-size
    kernel models for large data sets", Comput. Stat. Data Anal. 54 (2010) 1484–1504.
    M. Girolami, "Orthogonal series density estimation and the kernel eigenvalue
    problem", Neural Computation 14 (2002) 669–688.
    """
    X = _matrix("X", X)
    sigma2 = _positive("sigma2", sigma2)
    n = X.shape[0]
    size = int(size)
    if size < 1:
        raise ValueError(f"the number of prototypes must be at least 1, got {size}")
    if size >= n:
        return np.arange(n)
    rng = np.random.default_rng(random_state)
    chosen = rng.choice(n, size=size, replace=False)
    in_set = np.zeros(n, dtype=bool)
    in_set[chosen] = True
    points = X[chosen].copy()
    sq_norms = np.sum(points * points, axis=1)
    K = rbf_kernel(points, points, sigma2)
    row_sums = K.sum(axis=1)
    n_swaps = max(2000, 10 * size) if n_swaps is None else int(n_swaps)
    members = rng.integers(0, size, n_swaps)
    candidates = rng.integers(0, n, n_swaps)
    for i, c in zip(members, candidates):
        if in_set[c]:
            continue
        x = X[c]
        k = np.exp(-np.maximum(sq_norms - 2.0 * points @ x + x @ x, 0.0) / sigma2)
        # change of Σ K over the set: drop row+column i, add the candidate's (diag = 1)
        change = -2.0 * (row_sums[i] - 1.0) + 2.0 * (k.sum() - k[i])
        if change < 0.0:
            in_set[chosen[i]], in_set[c] = False, True
            k[i] = 1.0
            row_sums += k - K[:, i]
            row_sums[i] = k.sum()
            K[:, i] = k
            K[i, :] = k
            chosen[i] = c
            points[i] = x
            sq_norms[i] = x @ x
    return chosen


class FixedSizeLSSVM(_KernelModel):
    """Fixed-size LS-SVM regression: Nyström features on M prototypes, primal ridge.

    Parameters
    ----------
    gamma : float
        Regularisation constant γ > 0 (same meaning as in :class:`LSSVMRegressor`).
    sigma2 : float
        RBF bandwidth σ² > 0.
    prototypes : int or array_like, default 200
        Number M of prototypes selected from the training inputs by quadratic Rényi
        entropy, or an (M, d) array of prototype points to use as given.
    entropy_sigma2 : float, optional
        Bandwidth of the entropy criterion; default :func:`renyi_bandwidth` of the data
        (independent of σ², so tuning σ² does not move the prototypes).
    n_swaps : int, optional
        Swaps proposed by :func:`select_prototypes`.
    eigen_tolerance : float, default 1e-10
        Eigenvalues of the prototype kernel matrix below ``eigen_tolerance·λ_max`` are
        dropped (the Nyström map is numerically undefined there).
    random_state : int, default 0
        Seed of the prototype selection.

    Attributes
    ----------
    support_ : numpy.ndarray, shape (M, d)
        Prototype points.
    prototype_indices_ : numpy.ndarray of int or None
        Their row indices in the training inputs (None when prototypes were given).
    coef_ : numpy.ndarray, shape (m,)
        Primal weights w on the m ≤ M retained Nyström features.
    alpha_ : numpy.ndarray, shape (M,)
        The same model as coefficients on K(x, prototype_j).
    b_ : float
        Bias.

    Notes
    -----
    With K_MM = UΛUᵀ the eigen-decomposition of the prototype kernel matrix, the
    Nyström feature map is φ̂(x) = Λ^(−1/2)Uᵀ k_M(x), k_M(x)_j = K(x, p_j), so
    φ̂(x)ᵀφ̂(z) = k_M(x)ᵀK_MM⁻¹k_M(z) approximates K(x, z) (exactly on the prototypes).
    The primal problem min ½‖w‖² + (γ/2)Σ(y_k − wᵀφ̂(x_k) − b)² gives the normal equations

        [ ΦᵀΦ + I/γ   Φᵀ1 ] [ w ]   [ Φᵀy ]
        [ 1ᵀΦ          N  ] [ b ] = [ 1ᵀy ],

    symmetric positive definite, solved by Cholesky (``assume_a='pos'``).  ΦᵀΦ is
    accumulated over row blocks, so memory is O(M²) whatever N.  When the prototypes are
    all training points the model equals the dual LS-SVM (up to dropped eigenvalues).

    References
    ----------
    Suykens et al. (2002), *Least Squares Support Vector Machines*, §6.5 (fixed-size
    LS-SVM).  C.K.I. Williams, M. Seeger, "Using the Nyström method to speed up kernel
    machines", NIPS 13 (2001).  K. De Brabanter et al., "Fixed-size LS-SVM applied to the
    Wiener-Hammerstein benchmark", IFAC Proceedings Volumes 42(10) (2009) 826–831.
    """

    def __init__(self, gamma: float = 1.0, sigma2: float = 1.0, *, prototypes=200,
                 entropy_sigma2: float | None = None, n_swaps: int | None = None,
                 eigen_tolerance: float = 1e-10, random_state: int = 0):
        self.gamma = gamma
        self.sigma2 = sigma2
        self.prototypes = prototypes
        self.entropy_sigma2 = entropy_sigma2
        self.n_swaps = n_swaps
        self.eigen_tolerance = eigen_tolerance
        self.random_state = random_state

    def fit(self, X, y) -> FixedSizeLSSVM:
        """Select the prototypes (unless given) and solve the primal ridge problem.

        Parameters
        ----------
        X : array_like, shape (N, d) or (N,)
        y : array_like, shape (N,)

        Returns
        -------
        self
        """
        gamma = _positive("gamma", self.gamma)
        sigma2 = _positive("sigma2", self.sigma2)
        X = _matrix("X", X)
        y = _vector("y", y, X.shape[0])
        if np.ndim(self.prototypes) == 0:
            entropy_sigma2 = (renyi_bandwidth(X) if self.entropy_sigma2 is None
                              else self.entropy_sigma2)
            self.prototype_indices_ = select_prototypes(
                X, self.prototypes, entropy_sigma2, n_swaps=self.n_swaps,
                random_state=self.random_state)
            centres = X[self.prototype_indices_]
        else:
            centres = _matrix("prototypes", self.prototypes)
            if centres.shape[1] != X.shape[1]:
                raise ValueError(f"prototypes have {centres.shape[1]} features, X has "
                                 f"{X.shape[1]}")
            self.prototype_indices_ = None
        eigenvalues, vectors = linalg.eigh(rbf_kernel(centres, centres, sigma2))
        keep = eigenvalues > self.eigen_tolerance * eigenvalues[-1]
        projection = vectors[:, keep] / np.sqrt(eigenvalues[keep])   # k_M(x) → φ̂(x)
        m = projection.shape[1]
        normal = np.zeros((m + 1, m + 1))
        rhs = np.zeros(m + 1)
        rows = max(1, _CHUNK_ENTRIES // max(centres.shape[0], m))
        for start in range(0, X.shape[0], rows):
            features = np.empty((min(rows, X.shape[0] - start), m + 1))
            features[:, :m] = rbf_kernel(X[start:start + rows], centres, sigma2) @ projection
            features[:, m] = 1.0
            normal += features.T @ features
            rhs += features.T @ y[start:start + rows]
        normal[np.arange(m), np.arange(m)] += 1.0 / gamma
        solution = linalg.solve(normal, rhs, assume_a="pos", check_finite=False)
        self.coef_ = solution[:m]
        self.b_ = float(solution[m])
        self.alpha_ = projection @ self.coef_
        self.support_ = centres.copy()
        return self


# ----------------------------------------------------------------------------- tuning
@dataclass(frozen=True)
class TuningResult:
    """Outcome of :func:`tune`: the best point and every evaluation made."""

    gamma: float
    sigma2: float
    cost: float
    evaluations: tuple[tuple[float, float, float], ...]   # (γ, σ², cost) in call order


def tune(cost: Callable[[float, float], float], *, gamma=(1e-2, 1e6),
         sigma2=(1e-2, 1e3), grid: int = 7, start: tuple[float, float] | None = None,
         refine: bool = True, max_refine: int = 40,
         tolerance: float = 0.02) -> TuningResult:
    """Minimise a cross-validation cost over (γ, σ²): log grid, then Nelder–Mead.

    Parameters
    ----------
    cost : callable
        ``cost(gamma, sigma2) -> float``, smaller is better; e.g. :func:`kfold_cost` or
        :meth:`NARX.simulation_cost` (free-run simulation error).  Non-finite values are
        treated as +inf.
    gamma, sigma2 : (low, high) or float
        Search range (searched in log10), or a number to keep that parameter fixed.
    grid : int
        Grid points per searched parameter, evenly spaced in log10 (grid ≥ 2).
    start : (gamma, sigma2), optional
        Skip the grid and refine from this point (must lie in the ranges).
    refine : bool
        Run the Nelder–Mead refinement (log10 space, within the ranges).
    max_refine : int
        Cost evaluations allowed to the refinement.
    tolerance : float
        Simplex size [decades] at which the refinement stops.

    Returns
    -------
    TuningResult
        Best (γ, σ², cost) over the grid and the refinement.

    Notes
    -----
    Deterministic: no random numbers; the same cost gives the same result.  The grid
    gives a global view (as LS-SVMlab's ``tunelssvm`` does with coupled simulated
    annealing), the simplex polishes the best grid point; the first simplex step is one
    grid spacing.
    """
    names = ("gamma", "sigma2")
    specs = (gamma, sigma2)
    fixed, bounds = {}, {}
    for name, spec in zip(names, specs):
        if np.ndim(spec) == 0:
            fixed[name] = _positive(name, spec)
        else:
            low, high = (_positive(name, v) for v in spec)
            if not low < high:
                raise ValueError(f"{name} range must be (low, high) with low < high")
            bounds[name] = (math.log10(low), math.log10(high))
    free = list(bounds)
    record: dict[tuple, float] = {}
    order: list[tuple[float, float, float]] = []

    def point(logs) -> dict:
        values = dict(fixed)
        values.update({n: 10.0 ** float(v) for n, v in zip(free, logs)})
        return values

    def evaluate(logs) -> float:
        key = tuple(round(float(v), 9) for v in logs)
        if key not in record:
            values = point(key)
            value = float(cost(values["gamma"], values["sigma2"]))
            record[key] = value if math.isfinite(value) else math.inf
            order.append((values["gamma"], values["sigma2"], record[key]))
        return record[key]

    if not free:
        evaluate(())
        refine = False
    elif start is None:
        if grid < 2:
            raise ValueError("grid must be at least 2")
        axes = [np.linspace(*bounds[n], grid) for n in free]
        for logs in np.array(np.meshgrid(*axes, indexing="ij")).reshape(len(free), -1).T:
            evaluate(logs)
    else:
        start_values = dict(zip(names, start))
        logs = []
        for n in free:
            value = math.log10(_positive(n, start_values[n]))
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
        steps = np.array([(bounds[n][1] - bounds[n][0]) / max(grid - 1, 1) for n in free])
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
    if not math.isfinite(record[best]):
        raise ValueError("the cost was not finite at any evaluated (gamma, sigma2)")
    values = point(best)
    return TuningResult(values["gamma"], values["sigma2"], record[best], tuple(order))


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
    X = _matrix("X", X)
    y = _vector("y", y, X.shape[0])
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


# ----------------------------------------------------------------------------- NARX
def _experiments(name: str, data) -> tuple[list[np.ndarray], bool]:
    """One 1-D array or a list of them → (list of 1-D arrays, whether it was one)."""
    if isinstance(data, (list, tuple)) and data and all(np.ndim(d) == 1 for d in data):
        return [_vector(f"{name}[{i}]", d) for i, d in enumerate(data)], False
    array = np.asarray(data, dtype=float)
    if array.ndim == 1:
        return [_vector(name, array)], True
    raise ValueError(f"{name} must be a 1-D array or a list of 1-D arrays (one per "
                     f"experiment)")


def narx_regressors(u, y, na: int, nb: int, delay: int = 1
                    ) -> tuple[np.ndarray, np.ndarray]:
    """NARX regression rows, built inside each experiment only.

    Parameters
    ----------
    u, y : array_like or list of array_like
        Input and output of one experiment (1-D) or of several (lists, pairwise of
        equal length).
    na, nb, delay : int
        Output lags, input lags and input delay.

    Returns
    -------
    X : numpy.ndarray, shape (rows, na + nb)
        Rows x_t = [y_{t−1}, …, y_{t−na}, u_{t−delay}, …, u_{t−delay−nb+1}].
    target : numpy.ndarray, shape (rows,)
        y_t, for t = t0 … N−1 of every experiment, t0 = max(na, delay + nb − 1): a window
        never reaches into another experiment.
    """
    us, ys = _experiments("u", u)[0], _experiments("y", y)[0]
    if len(us) != len(ys):
        raise ValueError(f"u has {len(us)} experiments, y has {len(ys)}")
    start = max(na, delay + nb - 1)
    blocks, targets = [], []
    for k, (ue, ye) in enumerate(zip(us, ys)):
        if ue.size != ye.size:
            raise ValueError(f"experiment {k}: u has {ue.size} samples, y has {ye.size}")
        if ye.size <= start:
            raise ValueError(f"experiment {k} has {ye.size} samples; at least "
                             f"{start + 1} are needed for these lags")
        t = np.arange(start, ye.size)
        columns = [ye[t - i] for i in range(1, na + 1)]
        columns += [ue[t - delay - j] for j in range(nb)]
        blocks.append(np.column_stack(columns))
        targets.append(ye[start:])
    return np.vstack(blocks), np.concatenate(targets)


class NARX:
    """LS-SVM NARX model y_t = f(y_{t−1..t−na}, u_{t−delay..t−delay−nb+1}) + e_t.

    The black-box reference of the identification engines: f is an LS-SVM (dual,
    ``engine="full"``) or a fixed-size LS-SVM (``engine="fixed-size"``, for long
    records) on standardised signals.

    Parameters
    ----------
    na : int, default 2
        Number of past outputs.
    nb : int, default 2
        Number of past inputs.
    delay : int, default 1
        Input delay (0 lets u_t act on y_t).
    gamma, sigma2 : float or None
        LS-SVM hyper-parameters (σ² in standardised regressor units).  ``None`` tunes
        that parameter by :func:`tune` on the free-run simulation error of held-out
        data (:meth:`simulation_cost`).
    engine : {"full", "fixed-size"}
        Dual LS-SVM (N ≲ 5 000 rows) or :class:`FixedSizeLSSVM`.
    prototypes : int, default 300
        Prototypes of the fixed-size engine.
    folds : int, default 3
        Folds of the tuning cost.
    n_init : int, optional
        Initialisation window (measured outputs) of the held-out simulations during
        tuning; default :attr:`init_length`.
    tuning : dict, optional
        Extra keyword arguments of :func:`tune` (ranges, grid, max_refine, ...).
        Default: 5 x 5 grid, γ ∈ [1e-1, 1e7], σ² ∈ [0.01·d, 1000·d] with d = na + nb
        (lagged samples of an oversampled signal are strongly correlated, so the useful
        σ² can be far above d: about 80·d on Silverbox).
    random_state : int, default 0
        Seed of the prototype selection.

    Attributes
    ----------
    regressor_ : LSSVMRegressor or FixedSizeLSSVM
        The fitted map f (standardised units).
    gamma_, sigma2_ : float
        Hyper-parameters used (tuned or given).
    tuning_ : TuningResult or None
        Tuning record when a parameter was tuned.
    u_mean_, u_std_, y_mean_, y_std_ : float
        Standardisation of the training signals.
    n_rows_ : int
        Regression rows used (all experiments).

    Notes
    -----
    :meth:`predict` is the one-step-ahead predictor (measured past outputs enter every
    step); :meth:`simulate` is the free run (only an initialisation window of measured
    outputs, then the model's own outputs).  The free-run error is the figure to report
    and to tune on; one-step errors are usually far smaller (identification.md §1.5).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> u = rng.uniform(-1.0, 1.0, 400)
    >>> y = np.zeros(400)
    >>> for t in range(1, 400):
    ...     y[t] = 0.6 * y[t - 1] + np.tanh(u[t - 1])
    >>> model = NARX(na=1, nb=1, gamma=1e3, sigma2=2.0).fit(u[:300], y[:300])
    >>> y_sim = model.simulate(u[300:], y[300:301])      # free run from one sample
    >>> bool(nrmse(y[301:], y_sim[1:]) < 0.05)
    True
    """

    def __init__(self, na: int = 2, nb: int = 2, delay: int = 1,
                 gamma: float | None = None, sigma2: float | None = None, *,
                 engine: str = "full", prototypes: int = 300, folds: int = 3,
                 n_init: int | None = None, tuning: dict | None = None,
                 random_state: int = 0):
        self.na = na
        self.nb = nb
        self.delay = delay
        self.gamma = gamma
        self.sigma2 = sigma2
        self.engine = engine
        self.prototypes = prototypes
        self.folds = folds
        self.n_init = n_init
        self.tuning = tuning
        self.random_state = random_state

    # -- structure
    @property
    def init_length(self) -> int:
        """Samples before the first regression row: max(na, delay + nb − 1)."""
        return max(self.na, self.delay + self.nb - 1)

    def _check_structure(self) -> None:
        for name in ("na", "nb", "delay"):
            value = getattr(self, name)
            if not isinstance(value, (int, np.integer)) or value < 0:
                raise ValueError(f"{name} must be a non-negative integer, got {value!r}")
        if self.na + self.nb == 0:
            raise ValueError("na + nb must be at least 1")
        if self.engine not in ("full", "fixed-size"):
            raise ValueError(f"engine must be 'full' or 'fixed-size', got {self.engine!r}")

    def _make_regressor(self, gamma, sigma2, prototypes=None):
        if self.engine == "full":
            return LSSVMRegressor(gamma, sigma2)
        return FixedSizeLSSVM(gamma, sigma2, random_state=self.random_state,
                              prototypes=self.prototypes if prototypes is None
                              else prototypes)

    # -- standardisation
    @staticmethod
    def _standardisation(us, ys) -> tuple[float, float, float, float]:
        u_all, y_all = np.concatenate(us), np.concatenate(ys)
        return (float(u_all.mean()), float(u_all.std()) or 1.0,
                float(y_all.mean()), float(y_all.std()) or 1.0)

    def _scaled(self, us, ys, scaling=None):
        u_mean, u_std, y_mean, y_std = scaling or (self.u_mean_, self.u_std_,
                                                   self.y_mean_, self.y_std_)
        return [(u - u_mean) / u_std for u in us], [(y - y_mean) / y_std for y in ys]

    def _rows(self, us, ys):
        return narx_regressors(us, ys, self.na, self.nb, self.delay)

    # -- fitting
    def fit(self, u, y) -> NARX:
        """Identify f from one or several experiments.

        Parameters
        ----------
        u, y : array_like or list of array_like
            Input and output [any units] of one experiment (1-D arrays) or several
            (lists of 1-D arrays); lag windows never cross experiments.

        Returns
        -------
        self
        """
        self._check_structure()
        us, ys = _experiments("u", u)[0], _experiments("y", y)[0]
        self._rows(us, ys)                      # shape checks before any statistics
        scaling = self._standardisation(us, ys)
        self.u_mean_, self.u_std_, self.y_mean_, self.y_std_ = scaling
        us, ys = self._scaled(us, ys)
        self.tuning_ = None
        if self.gamma is None or self.sigma2 is None:
            d = self.na + self.nb
            options = {"gamma": (1e-1, 1e7) if self.gamma is None else self.gamma,
                       "sigma2": (0.01 * d, 1e3 * d) if self.sigma2 is None
                       else self.sigma2, "grid": 5}
            options.update(self.tuning or {})
            self.tuning_ = tune(self._scaled_simulation_cost(us, ys), **options)
            self.gamma_, self.sigma2_ = self.tuning_.gamma, self.tuning_.sigma2
        else:
            self.gamma_ = _positive("gamma", self.gamma)
            self.sigma2_ = _positive("sigma2", self.sigma2)
        X, target = self._rows(us, ys)
        self.regressor_ = self._make_regressor(self.gamma_, self.sigma2_).fit(X, target)
        self.n_rows_ = X.shape[0]
        return self

    def simulation_cost(self, u, y) -> Callable[[float, float], float]:
        """Free-run cross-validation cost ``cost(gamma, sigma2)`` on held-out data.

        With at least ``folds`` experiments, whole experiments are held out (fold k
        holds experiments k, k + folds, …); otherwise every experiment is cut into
        ``folds`` contiguous segments and fold k holds the k-th segment of each, the
        remaining segments being separate training experiments.  Each held-out piece is
        simulated in free run from its first ``n_init`` measured outputs.  Signals are
        standardised with the statistics of all the data given, as in :meth:`fit`.

        Returns
        -------
        callable
            Mean squared free-run error after the initialisation windows, divided by
            the output variance (= NRMSE²) over all folds.
        """
        self._check_structure()
        us, ys = _experiments("u", u)[0], _experiments("y", y)[0]
        self._rows(us, ys)
        scaling = self._standardisation(us, ys)
        return self._scaled_simulation_cost(*self._scaled(us, ys, scaling))

    def _scaled_simulation_cost(self, us, ys):
        n_init = self.init_length if self.n_init is None else int(self.n_init)
        if n_init < self.init_length:
            raise ValueError(f"n_init={n_init} is shorter than the lag window "
                             f"{self.init_length}")
        folds = int(self.folds)
        if folds < 2:
            raise ValueError(f"folds must be at least 2, got {folds}")
        if len(us) >= folds:
            splits = [([e for e in range(len(us)) if e % folds != k],
                       [e for e in range(len(us)) if e % folds == k]) for k in range(folds)]
            pieces = [(u, y) for u, y in zip(us, ys)]
        else:
            pieces, index = [], []
            for u, y in zip(us, ys):
                cuts = np.array_split(np.arange(y.size), folds)
                if min(c.size for c in cuts) <= n_init + self.init_length:
                    raise ValueError(f"an experiment of {y.size} samples is too short "
                                     f"for {folds} tuning folds")
                index.append(list(range(len(pieces), len(pieces) + folds)))
                pieces += [(u[c], y[c]) for c in cuts]
            splits = [([p for e in index for j, p in enumerate(e) if j != k],
                       [e[k] for e in index]) for k in range(folds)]
        prepared = []
        for train, held in splits:
            X, target = self._rows([pieces[p][0] for p in train],
                                   [pieces[p][1] for p in train])
            protos = None
            if self.engine == "fixed-size":     # prototypes do not depend on (γ, σ²)
                protos = X[select_prototypes(X, self.prototypes, renyi_bandwidth(X),
                                             random_state=self.random_state)]
            prepared.append((X, target, protos, [pieces[p] for p in held]))

        def cost(gamma: float, sigma2: float) -> float:
            squared, count = 0.0, 0
            for X, target, protos, held in prepared:
                model = self._make_regressor(gamma, sigma2, protos).fit(X, target)
                for u, y in held:
                    y_sim = self._simulate_scaled(model, u, y[:n_init])
                    squared += float(np.sum((y[n_init:] - y_sim[n_init:]) ** 2))
                    count += y.size - n_init
            return squared / count

        return cost

    # -- use
    def _check_fitted(self) -> None:
        if not hasattr(self, "regressor_"):
            raise ValueError("NARX model is not fitted: call fit(u, y) first")

    def predict(self, u, y):
        """One-step-ahead prediction (NOT a simulation): uses the measured outputs.

        Parameters
        ----------
        u, y : array_like or list of array_like
            Measured input and output, one experiment or a list of them.

        Returns
        -------
        numpy.ndarray or list of numpy.ndarray
            ŷ_t = f(y_{t−1}, …, u_{t−delay}, …) for t ≥ :attr:`init_length`; the first
            ``init_length`` samples are copied from ``y`` (no prediction exists there).
        """
        self._check_fitted()
        us, single = _experiments("u", u)
        measured = _experiments("y", y)[0]
        if len(us) != len(measured):
            raise ValueError(f"u has {len(us)} experiments, y has {len(measured)}")
        out = []
        for ue, ye in zip(us, measured):
            if ue.size != ye.size:
                raise ValueError(f"u has {ue.size} samples, y has {ye.size}")
            X, _ = self._rows(*self._scaled([ue], [ye]))
            pred = ye.copy()
            pred[self.init_length:] = self.regressor_.predict(X) * self.y_std_ + self.y_mean_
            out.append(pred)
        return out[0] if single else out

    def simulate(self, u, y_init):
        """Free-run simulation: only ``y_init`` measured outputs, then the model's own.

        Parameters
        ----------
        u : array_like or list of array_like
            Input over the whole horizon (one experiment or a list).
        y_init : array_like or list of array_like
            Measured outputs of the initialisation window, y_0 … y_{n−1},
            n ≥ :attr:`init_length` (e.g. the benchmark's 50 samples).

        Returns
        -------
        numpy.ndarray or list of numpy.ndarray
            Output over the horizon; the first n samples are ``y_init``, the rest is
            the recursive simulation ŷ_t = f(ŷ_{t−1}, …, ŷ_{t−na}, u_{t−delay}, …).
        """
        self._check_fitted()
        us, single = _experiments("u", u)
        inits = _experiments("y_init", y_init)[0]
        if len(us) != len(inits):
            raise ValueError(f"u has {len(us)} experiments, y_init has {len(inits)}")
        out = []
        for ue, ie in zip(*self._scaled(us, inits)):
            out.append(self._simulate_scaled(self.regressor_, ue, ie) * self.y_std_
                       + self.y_mean_)
        for simulated, measured in zip(out, inits):
            simulated[:measured.size] = measured
        return out[0] if single else out

    def _simulate_scaled(self, model, u: np.ndarray, y_init: np.ndarray) -> np.ndarray:
        """Recursive simulation in standardised units.

        The RBF kernel factorises over the regressor coordinates, so the input part
        exp(−‖u-window − c_u‖²/σ²)·α_j is computed for a block of steps at once and only
        the output-lag part is evaluated inside the loop.
        """
        n, start, na = u.size, y_init.size, self.na
        if start < self.init_length:
            raise ValueError(f"y_init has {start} samples; at least {self.init_length} "
                             f"are needed")
        if start > n:
            raise ValueError(f"y_init ({start} samples) is longer than u ({n})")
        centres, coef, bias, s2 = model.support_, model.alpha_, model.b_, model.sigma2
        c_y, c_u = centres[:, :na], centres[:, na:]
        y = np.empty(n)
        y[:start] = y_init
        # −‖h − c_y‖²/σ² expanded; columns reversed so h = y[t−na:t] in time order
        lin = np.ascontiguousarray(2.0 * c_y[:, ::-1] / s2)
        offset = -np.sum(c_y * c_y, axis=1) / s2
        block = max(1, _CHUNK_ENTRIES // (4 * centres.shape[0]))
        for first in range(start, n, block):
            t = np.arange(first, min(first + block, n))
            if self.nb:
                window = np.column_stack([u[t - self.delay - j] for j in range(self.nb)])
                weights = rbf_kernel(window, c_u, s2) * coef
            else:
                weights = np.broadcast_to(coef, (t.size, coef.size))
            if na == 0:
                y[t] = weights.sum(axis=1) + bias
                continue
            for row, step in enumerate(t):
                history = y[step - na:step]                 # y_{t−na}, …, y_{t−1}
                z = lin @ history + offset - (history @ history) / s2
                y[step] = weights[row] @ np.exp(np.minimum(z, 0.0)) + bias
        return y


# ----------------------------------------------------------------------------- metrics
def _pair(y, y_hat) -> tuple[np.ndarray, np.ndarray]:
    y = _vector("y", np.ravel(y))
    return y, _vector("y_hat", np.ravel(y_hat), y.size)


def rmse(y, y_hat) -> float:
    """Root-mean-square error √(mean((y − ŷ)²)) [units of y]."""
    y, y_hat = _pair(y, y_hat)
    return float(np.sqrt(np.mean((y - y_hat) ** 2)))


def nrmse(y, y_hat) -> float:
    """RMSE divided by the standard deviation of y (population, ddof = 0) [-]."""
    y, y_hat = _pair(y, y_hat)
    return rmse(y, y_hat) / float(np.std(y))


def fit_percent(y, y_hat) -> float:
    """Fit index 100·(1 − ‖y − ŷ‖/‖y − ȳ‖) [%] (MATLAB ``compare``)."""
    y, y_hat = _pair(y, y_hat)
    return float(100.0 * (1.0 - np.linalg.norm(y - y_hat) / np.linalg.norm(y - y.mean())))


def max_abs_error(y, y_hat) -> float:
    """Largest absolute error max|y − ŷ| [units of y]."""
    y, y_hat = _pair(y, y_hat)
    return float(np.max(np.abs(y - y_hat)))


@dataclass(frozen=True)
class ResidualAnalysis:
    """Whiteness and independence tests of residuals (see :func:`residual_analysis`)."""

    lags: np.ndarray                      # 1 … max_lag
    autocorrelation: np.ndarray           # r_ee(τ) at ``lags``
    autocorrelation_ok: np.ndarray        # |r_ee(τ)| ≤ bound, per lag
    cross_lags: np.ndarray | None         # −max_lag … max_lag
    cross_correlation: np.ndarray | None  # r_eu(τ) at ``cross_lags``
    cross_correlation_ok: np.ndarray | None
    bound: float                          # z_{(1+confidence)/2}/√N

    @property
    def white(self) -> bool:
        """All autocorrelations inside the band."""
        return bool(np.all(self.autocorrelation_ok))


def residual_analysis(residuals, u=None, *, max_lag: int = 25,
                      confidence: float = 0.99) -> ResidualAnalysis:
    """Autocorrelation of residuals and residual↔input cross-correlation with bounds.

    Parameters
    ----------
    residuals : array_like, shape (N,)
        One-step prediction errors e_t (whiteness is a property of the predictor).
    u : array_like, shape (N,), optional
        Input, for the cross-correlation test.
    max_lag : int
        Largest lag τ tested (25 as MATLAB ``resid``).
    confidence : float
        Two-sided level of the band; 0.99 gives ±2.576/√N.

    Returns
    -------
    ResidualAnalysis

    Notes
    -----
    With centred signals, r_ee(τ) = Σ_t e_t e_{t−τ} / Σ_t e_t² and
    r_eu(τ) = Σ_t e_t u_{t−τ} / √(Σ e_t² Σ u_t²) (biased estimates; positive τ pairs the
    residual with earlier inputs).  Under whiteness (resp. independence) each is
    approximately N(0, 1/N), hence the band ±z/√N with z the normal quantile.
    """
    e = _vector("residuals", residuals)
    n = e.size
    if not 1 <= max_lag < n:
        raise ValueError(f"max_lag must be between 1 and N − 1, got {max_lag}")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    e = e - e.mean()
    energy = float(e @ e)
    if energy == 0.0:
        raise ValueError("residuals are constant: correlations are undefined")
    bound = float(special.ndtri(0.5 + confidence / 2.0)) / math.sqrt(n)
    lags = np.arange(1, max_lag + 1)
    auto = np.array([e[tau:] @ e[:-tau] for tau in lags]) / energy
    cross_lags = cross = cross_ok = None
    if u is not None:
        x = _vector("u", u, n)
        x = x - x.mean()
        scale = math.sqrt(energy * float(x @ x))
        if scale == 0.0:
            raise ValueError("u is constant: the cross-correlation is undefined")
        cross_lags = np.arange(-max_lag, max_lag + 1)
        cross = np.array([e[tau:] @ x[:n - tau] if tau >= 0 else e[:tau] @ x[-tau:]
                          for tau in cross_lags]) / scale
        cross_ok = np.abs(cross) <= bound
    return ResidualAnalysis(lags, auto, np.abs(auto) <= bound, cross_lags, cross,
                            cross_ok, bound)
