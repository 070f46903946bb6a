"""Fixed-size LS-SVM: Nyström features on M prototypes chosen by quadratic Rényi entropy,
ridge regression in the primal (memory O(M²), any N) (Suykens et al. 2002, ch. 6;
Espinoza, Suykens & De Moor, "Fixed-size least squares support vector machines: a large
scale application in electrical load forecasting", Computational Management Science 3,
2006).
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy import linalg

from certkit.ident.reuse import digest, kept
from certkit.ident.experiments import DataInputError, order, positive_number, signal
from certkit.ident.lssvm import (CHUNK_ENTRIES, KernelModel, kernel_expansion,
                                 feature_matrix, rbf_kernel)
from certkit.ident.signature import orders_positional

CUBIC_TERMS = ("cubes", "all")


# ------------------------------------------------------------------ fixed-size LS-SVM
def renyi_bandwidth(X) -> float:
    """Default σ² of the entropy criterion: the normal-reference (Silverman) rule.

    h² = s̄²·(4/((d + 2)N))^(2/(d+4)) with s̄² the mean variance of the columns; in the
    kernel convention exp(−‖x − z‖²/σ²) this is σ² = 2h².
    """
    X = feature_matrix("X", X)
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
    X = feature_matrix("X", X)
    sigma2 = positive_number("sigma2", sigma2)
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



def nystrom_map(centres: np.ndarray, sigma2: float, eigen_tolerance: float = 1e-10
                ) -> np.ndarray:
    """The matrix Λ^(−1/2)U (retained columns) that maps k_M(x) to the Nyström features.

    With K_MM = UΛUᵀ the prototype kernel matrix, φ̂(x) = Λ^(−1/2)Uᵀk_M(x) so that
    φ̂(x)ᵀφ̂(z) = k_M(x)ᵀK_MM⁻¹k_M(z) ≈ K(x, z), exact on the prototypes (Williams & Seeger
    2001; Suykens et al. 2002, §6.5).  Eigenvalues below ``eigen_tolerance·λ_max`` are
    dropped (the map is numerically undefined there).

    Returns
    -------
    numpy.ndarray, shape (M, m)
        ``k_M(x) @ result`` is φ̂(x) (m ≤ M features).
    """
    eigenvalues, vectors = linalg.eigh(rbf_kernel(centres, centres, sigma2))
    keep = eigenvalues > eigen_tolerance * eigenvalues[-1]
    return vectors[:, keep] / np.sqrt(eigenvalues[keep])



class FixedSizeLSSVM(KernelModel):
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
    linear : bool, default False
        Add an unpenalised linear part βᵀx: the partially linear LS-SVM
        ŷ(x) = βᵀx + θᵀc(x) + wᵀφ̂(x) + b of Espinoza et al. (2005), where only the kernel
        weights w carry the ridge 1/γ.  Outside the training data the RBF part fades and
        the model extrapolates by its parametric part instead of falling back to b.
    cubic : int, default 0
        Add unpenalised cubic monomials c(x) of the first ``cubic`` columns of x (a NARX
        row's first columns are its output lags y_{t−1}, y_{t−2}, …): the odd polynomial
        of a stiffening or softening spring (Duffing), which the RBF part cannot carry
        beyond the training amplitudes.  Requires ``linear=True``.
    cubic_terms : {"cubes", "all"}, default "cubes"
        The monomials: x_i³ for each of those columns, or every degree-3 monomial
        x_i·x_j·x_k of them (i ≤ j ≤ k).

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
    linear_ : numpy.ndarray, shape (d,)
        β (zeros without ``linear``).
    cubic_ : numpy.ndarray, shape (k,)
        θ, the weights of the cubic monomials (empty without ``cubic``).
    monomials_ : numpy.ndarray of int, shape (k, 3)
        Column indices of each cubic monomial (x_i·x_j·x_k).

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
    With a parametric part, the columns x and c(x) join the bias column 1 in the second
    block row and column: unpenalised, like b (Espinoza et al. 2005, eq. (10) in the
    primal).  Without kernel features (γ → 0) the model is the least-squares fit of the
    parametric part alone.  When those columns are linearly dependent (fewer rows than
    parameters, a constant column) the system is singular and the minimum-norm solution
    is taken (``scipy.linalg.lstsq``).

    References
    ----------
    Suykens et al. (2002), *Least Squares Support Vector Machines*, §6.5 (fixed-size
    LS-SVM).  M. Espinoza, J.A.K. Suykens, B. De Moor, "Kernel based partially linear
    models and nonlinear identification", IEEE Trans. Automatic Control 50(10) (2005)
    1602–1606; M. Espinoza, K. Pelckmans, L. Hoegaerts, J.A.K. Suykens, B. De Moor, "A
    comparative study of LS-SVM's applied to the Silver box identification problem",
    IFAC NOLCOS 2004 (partially linear fixed-size LS-SVM NARX).  C.K.I. Williams, M. Seeger, "Using the Nyström method to speed up kernel
    machines", NIPS 13 (2001).  K. De Brabanter et al., "Fixed-size LS-SVM applied to the
    Wiener-Hammerstein benchmark", IFAC Proceedings Volumes 42(10) (2009) 826–831.
    """

    @orders_positional()
    def __init__(self, *, gamma: float = 1.0, sigma2: float = 1.0, prototypes=200,
                 entropy_sigma2: float | None = None, n_swaps: int | None = None,
                 eigen_tolerance: float = 1e-10, random_state: int = 0,
                 linear: bool = False, cubic: int = 0, cubic_terms: str = "cubes"):
        self.gamma = gamma
        self.sigma2 = sigma2
        self.prototypes = prototypes
        self.entropy_sigma2 = entropy_sigma2
        self.n_swaps = n_swaps
        self.eigen_tolerance = eigen_tolerance
        self.random_state = random_state
        self.linear = linear
        self.cubic = cubic
        self.cubic_terms = cubic_terms

    def _monomials(self, n_features: int) -> np.ndarray:
        """(k, 3) column indices of the cubic monomials (checks the options)."""
        cubic = order("cubic", self.cubic)
        if cubic and not self.linear:
            raise DataInputError("cubic", "expected linear=True with cubic terms (the "
                                          "parametric part is linear plus cubic), found "
                                          "linear=False")
        if cubic > n_features:
            raise DataInputError("cubic", f"expected at most the {n_features} columns of "
                                          f"X, found {cubic}")
        if self.cubic_terms not in CUBIC_TERMS:
            raise DataInputError("cubic_terms", f"expected one of {', '.join(CUBIC_TERMS)}, "
                                                f"found {self.cubic_terms!r}")
        if self.cubic_terms == "cubes":
            combos = [(i, i, i) for i in range(cubic)]
        else:
            combos = list(itertools.combinations_with_replacement(range(cubic), 3))
        return np.array(combos, dtype=int).reshape(-1, 3)

    def _parametric(self, X: np.ndarray) -> np.ndarray:
        """Unpenalised columns of the rows X: [x (with ``linear``), c(x), 1]."""
        columns = [X] if self.linear else []
        if self.monomials_.size:
            columns.append(np.prod(X[:, self.monomials_], axis=2))
        columns.append(np.ones((X.shape[0], 1)))
        return np.hstack(columns)

    def _normal_equations(self, X: np.ndarray, y: np.ndarray, centres: np.ndarray,
                          sigma2: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The Nyström projection and the normal equations ΦᵀΦ, Φᵀy of the primal ridge
        problem without its penalty (Φ = [φ̂(x), parametric columns]): all but γ."""
        projection = nystrom_map(centres, sigma2, self.eigen_tolerance)   # k_M(x) → φ̂(x)
        m = projection.shape[1]
        q = self._parametric(X[:1]).shape[1]          # [x,] [c(x),] 1: unpenalised
        normal = np.zeros((m + q, m + q))
        rhs = np.zeros(m + q)
        rows = max(1, CHUNK_ENTRIES // max(centres.shape[0], m))
        for start in range(0, X.shape[0], rows):
            block = X[start:start + rows]
            features = np.empty((block.shape[0], m + q))
            features[:, :m] = rbf_kernel(block, centres, sigma2) @ projection
            features[:, m:] = self._parametric(block)
            normal += features.T @ features
            rhs += features.T @ y[start:start + rows]
        return projection, normal, rhs

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
        gamma = positive_number("gamma", self.gamma)
        sigma2 = positive_number("sigma2", self.sigma2)
        X = feature_matrix("X", X)
        y = signal("y", y, X.shape[0])
        if np.ndim(self.prototypes) == 0:
            entropy_sigma2 = (renyi_bandwidth(X) if self.entropy_sigma2 is None
                              else self.entropy_sigma2)
            self.prototype_indices_ = kept(
                "prototypes", digest(X, self.prototypes, entropy_sigma2, self.n_swaps,
                                           self.random_state),
                lambda: select_prototypes(X, self.prototypes, entropy_sigma2,
                                          n_swaps=self.n_swaps,
                                          random_state=self.random_state))
            centres = X[self.prototype_indices_]
        else:
            centres = feature_matrix("prototypes", self.prototypes)
            if centres.shape[1] != X.shape[1]:
                raise ValueError(f"prototypes have {centres.shape[1]} features, X has "
                                 f"{X.shape[1]}")
            self.prototype_indices_ = None
        self.monomials_ = self._monomials(X.shape[1])
        projection, normal, rhs = kept(
            "normal equations", digest(X, y, centres, sigma2, self.eigen_tolerance,
                                             self.linear, self.monomials_),
            lambda: self._normal_equations(X, y, centres, sigma2))
        m = projection.shape[1]
        q = normal.shape[0] - m                       # [x,] [c(x),] 1: unpenalised
        normal = normal.copy()
        normal[np.arange(m), np.arange(m)] += 1.0 / gamma
        try:
            solution = linalg.solve(normal, rhs, assume_a="pos", check_finite=False)
        except linalg.LinAlgError:       # unpenalised columns linearly dependent (few
            solution = linalg.lstsq(normal, rhs)[0]  # rows, a constant column): min. norm
        self.coef_ = solution[:m]
        theta = solution[m:]
        d = X.shape[1] if self.linear else 0
        self.linear_ = theta[:d] if self.linear else np.zeros(X.shape[1])
        self.cubic_ = theta[d:q - 1]
        self.b_ = float(theta[q - 1])
        self.alpha_ = projection @ self.coef_
        self.support_ = centres.copy()
        return self

    def _predict_rows(self, X: np.ndarray) -> np.ndarray:
        """ŷ(x) = Σ_j α_j K(x, p_j) + βᵀx + θᵀc(x) + b for checked rows X."""
        theta = np.concatenate([self.linear_ if self.linear else [], self.cubic_, [0.0]])
        return (kernel_expansion(X, self.support_, self.alpha_, self.b_, self.sigma2)
                + self._parametric(X) @ theta)
