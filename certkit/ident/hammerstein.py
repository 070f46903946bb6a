"""Hammerstein ARX identification with a least-squares support vector machine (LS-SVM).

Model (one output, one or several input channels u_t in R^m)::

    y_t = sum_{i=1..na} a_i y_{t-i} + sum_{j=0..nb-1} b_j f(u_{t-k-j}) + d + e_t

a static nonlinearity ``f`` (of the input vector) followed by a linear ARX filter, input
delay ``k``.  The estimator follows Goethals,
Pelckmans, Suykens & De Moor (2005): every product ``b_j f(.)`` is over-parametrised as its own
kernel function ``g_j(.) = w_j' phi(.)``, the LS-SVM dual of that convex problem is one linear
system, and ``b`` and ``f`` are recovered afterwards from the rank-one structure of the
estimated components.  The equations are written out in :class:`HammersteinLSSVM`'s Notes.

Choices, each explained where it is made:

* **Centering sum** over *all* training samples (of every experiment), the same set for every
  component ``g_j``; see :class:`HammersteinLSSVM`, Notes.
* **Solver**: Cholesky factorisation of the SPD block ``H = Omega_H + I/gamma`` and a small
  symmetric Schur-complement system in ``(d, a, beta)``; no explicit inverse is formed.
* **Normalisation** of the ``b``/``f`` scale ambiguity: unit static gain of the linear block by
  default, so that ``f`` is the static (steady-state) input-output curve in output units.
* **Several experiments** (drops): regression rows never take lags across an experiment
  boundary; the kernel blocks and the centering run over the union of all samples.
* **Long records**: ``engine="fixed-size"`` solves the same over-parametrised problem in the
  primal on Nystrom features of M prototypes (memory O((nb M)^2), any N); with every
  training sample a prototype it is the exact dual.
* **Units of sigma2**: the kernel acts on the inputs divided by ``input_scale`` (default: each
  channel's standard deviation over the training data), so sigma2 is in standardised units.

The RBF kernel is :func:`certkit.ident.lssvm.rbf_kernel`, ``K(x, z) = exp(-|x - z|^2 / sigma2)``
(LS-SVMlab convention, no factor 2).

References
----------
.. [1] I. Goethals, K. Pelckmans, J. A. K. Suykens, B. De Moor, "Identification of MIMO
   Hammerstein models using least squares support vector machines", Automatica 41 (2005)
   1263-1272.
.. [2] Seed paper (light amphibious airplane drop test), section 3, eqs. (14)-(27); see
   :class:`HammersteinLSSVM`, Notes, for where this module differs from its equations.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.linalg import LinAlgError, cho_factor, cho_solve, eigh, solve
from scipy.signal import lfilter, lfiltic

from sklearn.utils.validation import check_is_fitted

from certkit.ident.dynamic_model import DynamicModel
from certkit.ident.experiments import DataInputError, channels, order, positive_number
from certkit.ident.fixed_size import nystrom_map, renyi_bandwidth, select_prototypes
from certkit.ident.lssvm import CHUNK_ENTRIES, rbf_kernel
from certkit.ident.signature import orders_positional
from certkit.ident.sizing import choose_engine

NORMALISATIONS = ("static_gain", "b0", "unit_norm")

# A normalisation divides by sum(b), b_0 or 1 - sum(a); below this (relative) size the
# division would only amplify noise, so the user is asked to pick another normalisation.
DEGENERATE_NORMALISATION = 1e-6


def ar_poles(a: Sequence[float]) -> np.ndarray:
    """Poles of the AR part ``1 - sum_i a_i z^-i`` of an ARX model.

    Parameters
    ----------
    a : array_like, shape (na,)
        AR coefficients ``a_1 .. a_na`` in ``y_t = sum_i a_i y_{t-i} + ...`` [-].

    Returns
    -------
    numpy.ndarray
        The ``na`` complex roots of ``z^na - a_1 z^(na-1) - ... - a_na`` (empty when ``na = 0``).
    """
    a = np.asarray(a, dtype=float).ravel()
    return np.roots(np.concatenate(([1.0], -a))) if a.size else np.empty(0, dtype=complex)


def is_stable(a: Sequence[float]) -> bool:
    """True when every pole of ``1 - sum_i a_i z^-i`` lies strictly inside the unit circle."""
    return bool(np.all(np.abs(ar_poles(a)) < 1.0))


class HammersteinLSSVM(DynamicModel):
    r"""Hammerstein ARX model identified with an over-parametrised LS-SVM.

    Parameters
    ----------
    na : int, default 6
        Number of AR (denominator) coefficients ``a_1 .. a_na`` (may be 0: FIR Hammerstein).
    nb : int, default 4
        Number of numerator terms ``b_0 .. b_{nb-1}`` (lags k .. k+nb-1 of ``f(u)``).  The
        defaults are the seed paper's orders (denominator 6, four numerator terms).
    delay : int, default 0
        Input delay k (0: ``f(u_t)`` acts on ``y_t``).
    gamma : float, default 1e3
        LS-SVM regularisation constant (weight of the squared equation errors) [-].
    sigma2 : float, default 1.0
        RBF kernel width ``sigma^2`` in ``exp(-|(u - u')/s|^2 / sigma2)`` with ``s`` the
        ``input_scale`` [standardised input units^2 by default].  The seed's eq. (28) divides
        by ``2 sigma^2``: its ``sigma`` corresponds to ``sigma2 = 2 sigma^2``.
    input_scale : float, sequence of float or None, default None
        Scale ``s`` of each input channel in the kernel.  None: the channel's standard
        deviation over the training inputs (1 for a constant channel); 1.0 puts sigma2 in
        raw input units squared.
    engine : {"full", "fixed-size", "auto"}, default "full"
        The exact dual (O(N^2) memory: it refuses N samples whose kernel matrix would exceed
        :data:`certkit.ident.sizing.MEMORY_BUDGET`, naming the option that fits) or the
        fixed-size primal on Nystrom features of ``prototypes`` points (any N).  ``"auto"``:
        the dual up to :data:`~certkit.ident.sizing.AUTO_FULL_SAMPLES` (5 000) samples,
        the fixed-size primal above; ``engine_`` and ``engine_reason_`` say which and why.
    prototypes : int, default 100
        Prototypes M of the fixed-size engine, chosen among the training inputs by
        quadratic Renyi entropy.
    random_state : int, default 0
        Seed of the prototype selection.
    normalisation : {"static_gain", "b0", "unit_norm"}, default "static_gain"
        How the scale/sign ambiguity ``b f = (k b)(f / k)`` is fixed:

        * ``"static_gain"``: ``sum(b) = 1 - sum(a)``, i.e. the linear block has unit static gain;
          ``f(u) + d/(1 - sum(a))`` is then the steady-state output for a constant input ``u``
          (the quasi-static curve, in output units).  Not usable for integrating or
          differentiating linear blocks (ValueError).
        * ``"b0"``: ``b_0 = 1`` (not usable with a pure delay, ``b_0 = 0``).
        * ``"unit_norm"``: ``|b| = 1`` and the largest-magnitude ``b_j`` positive.
    refine_linear : bool, default False
        After recovering ``f``, re-estimate ``a``, ``b`` and ``d`` by ordinary least squares with
        ``f`` held fixed (then re-apply the normalisation).  Removes the regularisation bias of
        the dual estimate of ``a``; off by default so the plain method of [1]_ is reported.

    Attributes
    ----------
    a_ : ndarray, shape (na,)
        AR coefficients.
    engine_ : {"full", "fixed-size"}
        The engine used.
    engine_reason_ : str
        Why (given, or what ``engine="auto"`` compared).
    b_ : ndarray, shape (nb,)
        Numerator coefficients, normalised as chosen.
    d_ : float
        Offset (all constants of the model lumped together) [output unit].
    singular_values_ : ndarray, shape (nb,)
        Singular values of the component matrix ``G`` (``G_jk = g_j(u_k)``), largest first.
    singular_value_ratio_ : float
        ``S_1 / S_0``: near 0 when the components are collinear, as a Hammerstein system makes
        them; a large ratio says the data are not Hammerstein-like or the orders are wrong.
    poles_ : ndarray of complex, shape (na,)
        Roots of ``1 - sum_i a_i z^-i``.
    stable_ : bool
        Every pole strictly inside the unit circle.
    dual_coef_ : ndarray, shape (n_rows,)
        Lagrange multipliers ``alpha`` of the model equations (one per regression row);
        full engine only.
    centering_coef_ : ndarray, shape (nb,)
        Lagrange multipliers ``beta`` of the centering constraints; full engine only.
    support_inputs_ : ndarray, shape (N, n_inputs) or (M, n_inputs)
        The kernel centres of ``f`` in input units: every training input (full engine) or
        the prototypes (fixed-size).
    input_scale_ : ndarray, shape (n_inputs,)
        The scale ``s`` used.
    n_rows_ : int
        Number of regression rows (equations) used.
    n_features_in_ : int
        Number of input channels.

    Notes
    -----
    Over-parametrised model, rows ``t`` in ``T`` (per experiment ``t = r .. N_e - 1`` with
    ``r = max(na, k + nb - 1)`` (written here for ``k = 0``), zero-based, so no lag leaves
    its experiment)::

        y_t = sum_i a_i y_{t-i} + sum_j w_j' phi(u_{t-j}) + d + e_t              (M)

    Primal: minimise ``1/2 sum_j |w_j|^2 + gamma/2 sum_{t in T} e_t^2`` subject to (M) and the
    centering constraints ``sum_{k in C} w_j' phi(u_k) = 0`` (j = 0 .. nb-1).

    *Centering index range.*  ``C`` is the set of all ``N`` training samples (all
    experiments), the same set for every ``j``.  Using one common set is what keeps the
    estimates rank one: the constraints make ``g_j = b_j (f - mean_C f)``, with the *same*
    mean for every ``j``; centering each ``g_j`` over its own lagged rows ``{t - j}`` would
    subtract a different constant for each ``j`` and break ``G = b f'``.  The full set also
    matches [1]_ and the seed's eq. (17) sum ``k = 1 .. N``.

    Stationarity gives ``w_j = sum_{s in T} alpha_s phi(u_{s-j}) + beta_j sum_{k in C} phi(u_k)``,
    ``e_t = alpha_t / gamma``, ``sum_t alpha_t = 0`` and ``sum_t alpha_t y_{t-i} = 0``, hence the
    symmetric saddle-point (KKT) system::

        [ 0   0     1'    0   ] [ d     ]   [ 0   ]
        [ 0   0     Y_p   0   ] [ a     ] = [ 0   ]
        [ 1   Y_p'  H     K_0 ] [ alpha ]   [ y_T ]
        [ 0   0     K_0'  c I ] [ beta  ]   [ 0   ]

    with ``Omega_kl = K(u_k, u_l)`` over all samples, ``H = Omega_H + I/gamma``,
    ``(Omega_H)_ts = sum_j K(u_{t-j}, u_{s-j})``, ``(K_0)_tj = sum_{k in C} K(u_k, u_{t-j})``,
    ``c = 1' Omega 1`` and ``(Y_p)_it = y_{t-i}``.  With ``A = [1, Y_p', K_0]`` and
    ``D = diag(0, 0_na, c I)`` it is solved as ``(A' H^-1 A - D) z = A' H^-1 y_T`` for
    ``z = (d, a, beta)`` (Cholesky of ``H``), then ``alpha = H^-1 (y_T - A z)``.

    Recovery: ``g_j(u) = sum_s alpha_s K(u_{s-j}, u) + beta_j sum_k K(u_k, u)``; the matrix
    ``G_jk = g_j(u_k)`` is ideally ``b f'``.  Its leading singular pair gives ``b`` and
    ``f`` at the training inputs; for any input ``f(u) = b' g(u) / (b' b)`` (projection on
    ``b``), which is zero-mean over the training inputs (the constant sits in ``d``).

    *Fixed size.*  With the Nystrom map ``phi_hat(u) = Lambda^(-1/2) U' k_M(u)`` of the
    prototype kernel matrix ``K_MM = U Lambda U'`` (Williams & Seeger 2001; Suykens et al.
    2002, section 6.5) the same primal is solved directly: the centering constraints say
    ``w_j`` is orthogonal to ``phi_bar = sum_{k in C} phi_hat(u_k)``, so the features are
    projected, ``psi(u) = P phi_hat(u)`` with ``P = I - phi_bar phi_bar' / |phi_bar|^2``,
    and ``(a, w_0..w_{nb-1}, d)`` solve the ridge normal equations
    ``(Z'Z + R/gamma) theta = Z'y_T`` (rows ``z_t = [y_{t-1..t-na}, psi(u_{t-k-j}) for j, 1]``,
    ``R`` the identity on the ``w`` block, zero on ``a`` and ``d``), accumulated over row
    blocks.  ``G G' = W' (Psi' Psi) W`` (nb x nb) gives the singular pairs of ``G`` without
    forming it.  When the prototypes are all N training inputs, ``phi_hat`` reproduces the
    kernel on them and the solution is that of the dual (up to dropped eigenvalues).

    Differences from the seed paper's section 3 (whose indices are not consistent):
    eq. (14) uses one ``w`` for every lag -- here one ``w_j`` per lag, as eqs. (15)-(16);
    eq. (19) omits the lag, ``phi(u_k)`` must be ``phi(u_{k-j})`` (eq. (26) has it right);
    eqs. (11), (15), (13), (18) and (23) run the error/multiplier sums over ``k = r .. n``
    or ``1 .. N``, here everything is over the rows ``T`` only (``|T| = N - r`` per experiment,
    which is also the size the ``1_N`` and ``I_N`` blocks of eq. (27) must have); eq. (9)
    declares ``w`` a scalar (it is a feature-space vector) and eq. (20) differentiates by
    ``a_j`` but indexes the condition by ``i``.

    References
    ----------
    .. [1] I. Goethals, K. Pelckmans, J. A. K. Suykens, B. De Moor, Automatica 41 (2005)
       1263-1272.
    .. [3] J.A.K. Suykens, T. Van Gestel, J. De Brabanter, B. De Moor, J. Vandewalle, *Least
       Squares Support Vector Machines*, World Scientific, 2002, section 6.5 (fixed size).
    .. [4] C.K.I. Williams, M. Seeger, "Using the Nystrom method to speed up kernel
       machines", NIPS 13 (2001).
    .. [5] K. De Brabanter et al., "Optimized fixed-size kernel models for large data
       sets", Comput. Stat. Data Anal. 54 (2010) 1484-1504.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> u = rng.uniform(-1, 1, 300)
    >>> x = u + 0.5 * u**3
    >>> y = np.zeros_like(u)
    >>> for t in range(1, u.size):
    ...     y[t] = 0.5 * y[t - 1] + x[t] + 0.5 * x[t - 1]
    >>> model = HammersteinLSSVM(na=1, nb=2, gamma=1e6, sigma2=1.0).fit(u, y)
    >>> bool(model.stable_), round(float(model.a_[0]), 2)
    (True, 0.5)
    """


    # its earlier signature took (na, nb, gamma, sigma2, normalisation, refine_linear)
    @orders_positional(earlier=("gamma", "sigma2", "normalisation", "refine_linear"))
    def __init__(self, na: int = 6, nb: int = 4, *, delay: int = 0, gamma: float = 1e3,
                 sigma2: float = 1.0, engine: str = "full", prototypes: int = 100,
                 random_state: int = 0, normalisation: str = "static_gain",
                 refine_linear: bool = False, input_scale=None):
        self.na = na
        self.nb = nb
        self.delay = delay
        self.gamma = gamma
        self.sigma2 = sigma2
        self.engine = engine
        self.prototypes = prototypes
        self.random_state = random_state
        self.normalisation = normalisation
        self.refine_linear = refine_linear
        self.input_scale = input_scale

    # ------------------------------------------------------------------ helpers
    @property
    def init_length(self) -> int:
        """Samples before the first regression row of each experiment: max(na, k + nb - 1)."""
        return max(self.na, self.delay + self.nb - 1)

    def _check_hyperparameters(self) -> None:
        order("na", self.na)
        order("nb", self.nb, 1)
        order("delay", self.delay)
        positive_number("gamma", self.gamma)
        positive_number("sigma2", self.sigma2)
        if self.normalisation not in NORMALISATIONS:
            raise DataInputError("normalisation", f"expected one of {', '.join(NORMALISATIONS)}"
                                                  f", found {self.normalisation!r}")
        if self.engine != "full":
            order("prototypes", self.prototypes, 1)

    def _scale(self, u_all: np.ndarray) -> np.ndarray:
        if self.input_scale is None:
            spread = u_all.std(axis=0)
            return np.where(spread > 0, spread, 1.0)
        values = np.broadcast_to(np.asarray(self.input_scale, dtype=float), (u_all.shape[1],))
        for value in values:
            positive_number("input_scale", value)
        return values.copy()

    def _normalise(self, a: np.ndarray, b: np.ndarray) -> float:
        """Factor k so that k*b satisfies the chosen normalisation (f is divided by k)."""
        scale = np.linalg.norm(b)
        if self.normalisation == "static_gain":
            ar_gain = 1.0 - a.sum()
            if (abs(b.sum()) < DEGENERATE_NORMALISATION * scale
                    or abs(ar_gain) < DEGENERATE_NORMALISATION):
                raise DataInputError("normalisation", "static gain of the linear block is zero "
                                     "or infinite (sum(b) ~ 0 or sum(a) ~ 1): use "
                                     "normalisation='b0' or 'unit_norm'")
            return ar_gain / b.sum()
        if self.normalisation == "b0":
            if abs(b[0]) < DEGENERATE_NORMALISATION * scale:
                raise DataInputError("normalisation", "b_0 is ~0 (input delay?): use "
                                     "normalisation='static_gain' or 'unit_norm', or delay")
            return 1.0 / b[0]
        return float(np.sign(b[np.argmax(np.abs(b))])) / scale

    # ------------------------------------------------------------------ fitting
    def _fit(self, pairs) -> None:
        """Identify the model from a list of (input (n, m), output (n,)) experiments."""
        self._check_hyperparameters()
        lag = self.init_length
        for k, (uk, _) in enumerate(pairs):
            if uk.shape[0] <= lag:
                raise DataInputError(f"u[{k}]" if len(pairs) > 1 else "u",
                                     f"expected at least max(na, delay + nb - 1) + 1 = "
                                     f"{lag + 1} samples, found {uk.shape[0]} sample(s)")
        u_all = np.vstack([uk for uk, _ in pairs])
        y_all = np.concatenate([yk for _, yk in pairs])
        # the dual's kernel matrices span every sample (the centering runs over all of them)
        self.engine_, self.engine_reason_ = choose_engine(
            "HammersteinLSSVM", self.engine, u_all.shape[0], u_all.shape[0], self.prototypes)
        starts = np.cumsum([0] + [uk.shape[0] for uk, _ in pairs[:-1]])
        rows = np.concatenate([np.arange(s + lag, s + uk.shape[0])
                               for s, (uk, _) in zip(starts, pairs)])
        if rows.size < self.na + 2:
            raise DataInputError("u, y", f"expected more regression rows than the {self.na} AR "
                                         f"coefficients and the offset, found {rows.size}: "
                                         f"give longer experiments")
        self.input_scale_ = self._scale(u_all)
        scaled = u_all / self.input_scale_
        lagged = rows[:, None] - self.delay - np.arange(self.nb)[None, :]   # index of u_{t-k-j}
        y_past = y_all[rows[None, :] - np.arange(1, self.na + 1)[:, None]]  # (na, rows)
        solve_by = self._fit_dual if self.engine_ == "full" else self._fit_fixed_size
        a, d, weights_of, f_train, singular = solve_by(scaled, y_all, rows, lagged, y_past)

        u_svd, s_svd = singular
        b = u_svd[:, 0] * s_svd[0]
        k = self._normalise(a, b)
        b = k * b
        theta = weights_of(b / (b @ b))      # f(u) = K(u, centres) theta  (projection on b)

        if self.refine_linear:
            f_values = f_train(theta)
            regressors = np.column_stack([y_past.T, f_values[lagged], np.ones(rows.size)])
            coef, *_ = np.linalg.lstsq(regressors, y_all[rows], rcond=None)
            a, b, d = coef[:self.na], coef[self.na:self.na + self.nb], float(coef[-1])
            k = self._normalise(a, b)
            b, theta = k * b, theta / k

        self.a_ = np.asarray(a, dtype=float)
        self.b_ = b
        self.d_ = d
        self.singular_values_ = s_svd
        self.singular_value_ratio_ = float(s_svd[1] / s_svd[0]) if self.nb > 1 else 0.0
        self.poles_ = ar_poles(self.a_)
        self.stable_ = is_stable(self.a_)
        self.n_rows_ = int(rows.size)
        self._theta = theta

    def _fit_dual(self, u, y_all, rows, lagged, y_past):
        """The exact dual (KKT system of the Notes): Cholesky of H, Schur complement in z."""
        na, nb, n = self.na, self.nb, u.shape[0]
        omega = rbf_kernel(u, u, self.sigma2)
        omega_sum = omega.sum(axis=1)
        h = np.eye(rows.size) / self.gamma
        for j in range(nb):
            h += omega[np.ix_(lagged[:, j], lagged[:, j])]
        k0 = omega_sum[lagged]                                       # (rows, nb)
        c = omega_sum.sum()
        a_mat = np.column_stack([np.ones(rows.size), y_past.T, k0])
        h_factor = cho_factor(h, lower=True)
        hinv_a = cho_solve(h_factor, a_mat)
        hinv_y = cho_solve(h_factor, y_all[rows])
        schur = a_mat.T @ hinv_a
        schur[1 + na:, 1 + na:] -= c * np.eye(nb)
        z = solve(schur, a_mat.T @ hinv_y, assume_a="sym")
        alpha = hinv_y - hinv_a @ z
        d, a, beta = float(z[0]), z[1:1 + na], z[1 + na:]

        # Components g_j at the training inputs: g_j = Omega w_j with
        # w_j = scatter(alpha to u_{t-k-j}) + beta_j 1, so G = W' Omega.
        weights = np.column_stack([np.bincount(lagged[:, j], weights=alpha, minlength=n)
                                   for j in range(nb)]) + beta[None, :]
        g = weights.T @ omega
        u_svd, s_svd, _ = np.linalg.svd(g, full_matrices=False)
        self.dual_coef_ = alpha
        self.centering_coef_ = beta
        self.support_inputs_ = u * self.input_scale_
        self._centres = u
        self._weights = weights
        return a, d, (lambda v: weights @ v), (lambda theta: omega @ theta), (u_svd, s_svd)

    def _fit_fixed_size(self, u, y_all, rows, lagged, y_past):
        """The primal on projected Nystrom features (Notes, *Fixed size*), in row blocks."""
        na, nb, n = self.na, self.nb, u.shape[0]
        chosen = select_prototypes(u, self.prototypes, renyi_bandwidth(u),
                                   random_state=self.random_state)
        centres = u[chosen]
        projection = nystrom_map(centres, self.sigma2)          # k_M(u) -> phi_hat(u)
        m = projection.shape[1]

        def features(x):
            return rbf_kernel(x, centres, self.sigma2) @ projection

        block = max(1, CHUNK_ENTRIES // max(centres.shape[0], nb * m))
        phi_bar = np.zeros(m)
        for first in range(0, n, block):
            phi_bar += features(u[first:first + block]).sum(axis=0)
        unit = phi_bar / np.linalg.norm(phi_bar)

        def projected(x):
            phi = features(x)
            return phi - np.outer(phi @ unit, unit)

        size = na + nb * m + 1
        normal, rhs, gram = np.zeros((size, size)), np.zeros(size), np.zeros((m, m))
        for first in range(0, n, block):
            psi = projected(u[first:first + block])
            gram += psi.T @ psi
        for first in range(0, rows.size, block):
            t, lags = rows[first:first + block], lagged[first:first + block]
            low = int(lags.min())
            psi = projected(u[low:int(lags.max()) + 1])
            z = np.empty((t.size, size))
            z[:, :na] = y_past[:, first:first + block].T
            for j in range(nb):
                z[:, na + j * m:na + (j + 1) * m] = psi[lags[:, j] - low]
            z[:, -1] = 1.0
            normal += z.T @ z
            rhs += z.T @ y_all[t]
        ridge = np.arange(na, na + nb * m)
        normal[ridge, ridge] += 1.0 / self.gamma
        try:
            solution = solve(normal, rhs, assume_a="pos", check_finite=False)
        except LinAlgError:     # a or d not determined by the data (e.g. a constant input)
            solution = np.linalg.lstsq(normal, rhs, rcond=None)[0]
        a, d = solution[:na], float(solution[-1])
        w = solution[na:na + nb * m].reshape(nb, m).T             # (m, nb): w_j in columns
        eigenvalues, vectors = eigh(w.T @ gram @ w)              # G G' = W' Psi'Psi W
        descending = np.argsort(eigenvalues)[::-1]
        s_svd = np.sqrt(np.maximum(eigenvalues[descending], 0.0))
        u_svd = vectors[:, descending]
        # f(u) = psi(u)' w v = k_M(u)' projection P w v
        coefficients = projection - np.outer(projection @ unit, unit)
        self.prototype_indices_ = chosen
        self.support_inputs_ = centres * self.input_scale_
        self._centres = centres
        self._weights = coefficients @ w

        def f_train(theta):
            return np.concatenate([rbf_kernel(u[i:i + block], centres, self.sigma2) @ theta
                                   for i in range(0, n, block)])

        return a, d, (lambda v: coefficients @ (w @ v)), f_train, (u_svd, s_svd)

    # ------------------------------------------------------------------ evaluation
    def _kernel_to_centres(self, u: np.ndarray) -> np.ndarray:
        return rbf_kernel(u / self.input_scale_, self._centres, self.sigma2)

    def nonlinearity(self, u) -> np.ndarray:
        """Estimated static nonlinearity ``f(u)`` (normalised as chosen, zero-mean over training).

        Parameters
        ----------
        u : array_like, shape (n,) or (n, n_inputs)
            Input values [input units]; with one input channel any shape is accepted.

        Returns
        -------
        numpy.ndarray
            ``f(u)``, shape (n,) (or the shape of ``u`` for one channel).  With
            ``normalisation="static_gain"`` it is in output units: a constant input ``u``
            settles at ``f(u) + d / (1 - sum(a))``.
        """
        check_is_fitted(self)
        arr = np.asarray(u, dtype=float)
        if self.n_features_in_ == 1:
            flat = channels("u", arr.reshape(-1, 1)) if arr.size else np.empty((0, 1))
            return (self._kernel_to_centres(flat) @ self._theta).reshape(arr.shape)
        return self._kernel_to_centres(channels("u", arr, self.n_features_in_)) @ self._theta

    def components(self, u) -> np.ndarray:
        """Over-parametrised components ``g_j(u)`` (before the rank-one step), shape (nb, n)."""
        check_is_fitted(self)
        arr = channels("u", u, self.n_features_in_)
        return (self._kernel_to_centres(arr) @ self._weights).T

    def _forcing(self, u: np.ndarray) -> np.ndarray:
        """``sum_j b_j f(u_{t-k-j}) + d`` for every t >= k + nb - 1 (earlier entries
        meaningless)."""
        f = self._kernel_to_centres(u) @ self._theta
        lagged_b = np.concatenate([np.zeros(self.delay), self.b_])
        return np.convolve(f, lagged_b)[:u.shape[0]] + self.d_

    def _simulate_one(self, u: np.ndarray, y_init: np.ndarray) -> np.ndarray:
        """Free run: the linear IIR filter driven by ``f(u)``, fed back its own output."""
        n0 = y_init.size
        out = np.empty(u.shape[0])
        out[:n0] = y_init
        if n0 == u.shape[0]:
            return out
        den = np.concatenate(([1.0], -self.a_))
        forcing = self._forcing(u)[n0:]
        if self.na:
            zi = lfiltic([1.0], den, y_init[::-1][:self.na])   # y_{n0-1}, y_{n0-2}, ...
            out[n0:] = lfilter([1.0], den, forcing, zi=zi)[0]
        else:
            out[n0:] = forcing
        return out

    def _one_step(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        """``yhat_t = sum_i a_i y_{t-i} + sum_j b_j f(u_{t-k-j}) + d`` with measured ``y``."""
        out = y.copy()
        ar = np.zeros(y.size)
        for i, a_i in enumerate(self.a_, start=1):
            ar[i:] += a_i * y[:-i]
        lag = self.init_length
        out[lag:] = (ar + self._forcing(u))[lag:]
        return out
