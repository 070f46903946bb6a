"""Hammerstein ARX identification with a least-squares support vector machine (LS-SVM).

Model (single input, single output)::

    y_t = sum_{i=1..na} a_i y_{t-i} + sum_{j=0..nb-1} b_j f(u_{t-j}) + d + e_t

a static nonlinearity ``f`` followed by a linear ARX filter.  The estimator follows Goethals,
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
from scipy.linalg import cho_factor, cho_solve, solve
from scipy.signal import lfilter, lfiltic

from certkit.ident.experiments import experiments as experiments_of
from certkit.ident.experiments import signal
from certkit.ident.lssvm import rbf_kernel

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


class HammersteinLSSVM:
    r"""Hammerstein ARX model identified with an over-parametrised LS-SVM.

    Parameters
    ----------
    na : int, default 6
        Number of AR (denominator) coefficients ``a_1 .. a_na`` (may be 0: FIR Hammerstein).
    nb : int, default 4
        Number of numerator terms ``b_0 .. b_{nb-1}`` (lags 0 .. nb-1 of ``f(u)``).  The
        defaults are the seed paper's orders (denominator 6, four numerator terms).
    gamma : float, default 1e3
        LS-SVM regularisation constant (weight of the squared equation errors) [-].
    sigma2 : float, default 1.0
        RBF kernel width ``sigma^2`` in ``exp(-|u - u'|^2 / sigma2)`` [input unit^2].  The seed's
        eq. (28) divides by ``2 sigma^2``: its ``sigma`` corresponds to ``sigma2 = 2 sigma^2``.
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
        Lagrange multipliers ``alpha`` of the model equations (one per regression row).
    centering_coef_ : ndarray, shape (nb,)
        Lagrange multipliers ``beta`` of the centering constraints.
    support_inputs_ : ndarray, shape (N,)
        All training inputs (every experiment, concatenated).
    n_rows_ : int
        Number of regression rows (equations) used.

    Notes
    -----
    Over-parametrised model, rows ``t`` in ``T`` (per experiment ``t = r .. N_e - 1`` with
    ``r = max(na, nb - 1)``, zero-based, so no lag leaves its experiment)::

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

    def __init__(self, na: int = 6, nb: int = 4, gamma: float = 1e3, sigma2: float = 1.0,
                 normalisation: str = "static_gain", refine_linear: bool = False):
        self.na = na
        self.nb = nb
        self.gamma = gamma
        self.sigma2 = sigma2
        self.normalisation = normalisation
        self.refine_linear = refine_linear

    # ------------------------------------------------------------------ helpers
    @property
    def _lag(self) -> int:
        """Samples before the first regression row of each experiment: max(na, nb - 1)."""
        return max(self.na, self.nb - 1)

    def _check_hyperparameters(self) -> None:
        for name in ("na", "nb"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                # ValueError like every other bad hyper-parameter (one exception type to catch)
                raise ValueError(f"{name} must be an integer, got {value!r}")  # noqa: TRY004
        if self.na < 0 or self.nb < 1:
            raise ValueError(f"need na >= 0 and nb >= 1, got na={self.na}, nb={self.nb}")
        for name in ("gamma", "sigma2"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive finite number, got {value!r}")
        if self.normalisation not in NORMALISATIONS:
            raise ValueError(f"unknown normalisation {self.normalisation!r}; "
                             f"valid: {', '.join(NORMALISATIONS)}")

    def _kernel(self, x: np.ndarray, z: np.ndarray) -> np.ndarray:
        return rbf_kernel(x.reshape(-1, 1), z.reshape(-1, 1), self.sigma2)

    def _check_fitted(self) -> None:
        if not hasattr(self, "a_"):
            raise ValueError("model is not fitted yet: call fit(u, y) first")

    def _normalise(self, a: np.ndarray, b: np.ndarray) -> float:
        """Factor k so that k*b satisfies the chosen normalisation (f is divided by k)."""
        scale = np.linalg.norm(b)
        if self.normalisation == "static_gain":
            ar_gain = 1.0 - a.sum()
            if abs(b.sum()) < DEGENERATE_NORMALISATION * scale or abs(ar_gain) < DEGENERATE_NORMALISATION:
                raise ValueError("static gain of the linear block is zero or infinite "
                                 "(sum(b) ~ 0 or sum(a) ~ 1): use normalisation='b0' or 'unit_norm'")
            return ar_gain / b.sum()
        if self.normalisation == "b0":
            if abs(b[0]) < DEGENERATE_NORMALISATION * scale:
                raise ValueError("b_0 is ~0 (input delay?): use normalisation='static_gain' or 'unit_norm'")
            return 1.0 / b[0]
        return float(np.sign(b[np.argmax(np.abs(b))])) / scale

    # ------------------------------------------------------------------ fitting
    def fit(self, u, y) -> HammersteinLSSVM:
        """Identify the model from one experiment or a list of experiments.

        Parameters
        ----------
        u : array_like, shape (N,), or list of such arrays
            Input signal(s) [input unit].
        y : array_like, shape (N,), or list of such arrays
            Output signal(s), same lengths as ``u`` [output unit].  Lists are separate
            experiments: no regression row uses lags across an experiment boundary.

        Returns
        -------
        HammersteinLSSVM
            ``self``, fitted.

        Raises
        ------
        ValueError
            Bad hyper-parameters, shapes or lengths, non-finite data, an experiment shorter
            than ``max(na, nb - 1) + 1`` samples, too few rows in total, or a degenerate
            normalisation.
        """
        self._check_hyperparameters()
        experiments = experiments_of(u, y)[0]
        lag = self._lag
        for k, (uk, _) in enumerate(experiments):
            if uk.size <= lag:
                raise ValueError(f"experiment {k} has {uk.size} samples; at least "
                                 f"max(na, nb - 1) + 1 = {lag + 1} are needed")
        u_all = np.concatenate([uk for uk, _ in experiments])
        y_all = np.concatenate([yk for _, yk in experiments])
        starts = np.cumsum([0] + [uk.size for uk, _ in experiments[:-1]])
        rows = np.concatenate([np.arange(s + lag, s + uk.size)
                               for s, (uk, _) in zip(starts, experiments)])
        if rows.size < self.na + 2:
            raise ValueError(f"only {rows.size} regression rows for {self.na} AR coefficients "
                             f"and an offset: give longer experiments")

        na, nb, n = self.na, self.nb, u_all.size
        lagged = rows[:, None] - np.arange(nb)[None, :]             # index of u_{t-j}
        omega = self._kernel(u_all, u_all)
        omega_sum = omega.sum(axis=1)
        h = np.eye(rows.size) / self.gamma
        for j in range(nb):
            h += omega[np.ix_(lagged[:, j], lagged[:, j])]
        k0 = omega_sum[lagged]                                       # (rows, nb)
        c = omega_sum.sum()
        y_past = y_all[rows[None, :] - np.arange(1, na + 1)[:, None]]  # (na, rows)

        # Symmetric saddle-point system: Cholesky of the SPD block H, Schur complement in z.
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
        # w_j = scatter(alpha to u_{t-j}) + beta_j 1, so G = W' Omega.
        weights = np.column_stack([np.bincount(lagged[:, j], weights=alpha, minlength=n)
                                   for j in range(nb)]) + beta[None, :]
        g = weights.T @ omega
        u_svd, s_svd, _ = np.linalg.svd(g, full_matrices=False)
        b = u_svd[:, 0] * s_svd[0]

        k = self._normalise(a, b)
        b = k * b
        theta = weights @ b / (b @ b)        # f(u) = K(u, U) theta  (projection on b)

        if self.refine_linear:
            f_train = omega @ theta
            regressors = np.column_stack([y_past.T, f_train[lagged], np.ones(rows.size)])
            coef, *_ = np.linalg.lstsq(regressors, y_all[rows], rcond=None)
            a, b, d = coef[:na], coef[na:na + nb], float(coef[-1])
            k = self._normalise(a, b)
            b, theta = k * b, theta / k

        self.a_ = np.asarray(a, dtype=float)
        self.b_ = b
        self.d_ = d
        self.singular_values_ = s_svd
        self.singular_value_ratio_ = float(s_svd[1] / s_svd[0]) if nb > 1 else 0.0
        self.poles_ = ar_poles(self.a_)
        self.stable_ = is_stable(self.a_)
        self.dual_coef_ = alpha
        self.centering_coef_ = beta
        self.support_inputs_ = u_all
        self.n_rows_ = int(rows.size)
        self._weights = weights
        self._theta = theta
        return self

    # ------------------------------------------------------------------ evaluation
    def nonlinearity(self, u) -> np.ndarray:
        """Estimated static nonlinearity ``f(u)`` (normalised as chosen, zero-mean over training).

        Parameters
        ----------
        u : array_like
            Input values [input unit].

        Returns
        -------
        numpy.ndarray
            ``f(u)``, same shape as ``u``.  With ``normalisation="static_gain"`` it is in output
            units: a constant input ``u`` settles at ``f(u) + d / (1 - sum(a))``.
        """
        self._check_fitted()
        arr = np.asarray(u, dtype=float)
        if not np.all(np.isfinite(arr)):
            raise ValueError("u contains NaN or infinite values")
        return (self._kernel(arr.ravel(), self.support_inputs_) @ self._theta).reshape(arr.shape)

    def components(self, u) -> np.ndarray:
        """Over-parametrised components ``g_j(u)`` (before the rank-one step), shape (nb, len(u))."""
        self._check_fitted()
        arr = signal("u", u)
        return (self._kernel(arr, self.support_inputs_) @ self._weights).T

    def _forcing(self, u: np.ndarray) -> np.ndarray:
        """``sum_j b_j f(u_{t-j}) + d`` for every t >= nb - 1 (earlier entries meaningless)."""
        return np.convolve(self.nonlinearity(u), self.b_)[:u.size] + self.d_

    def simulate(self, u, y_init) -> np.ndarray:
        """Free-run simulation: the linear IIR filter driven by ``f(u)``, fed back its own output.

        Only the first ``len(y_init)`` measured outputs are used (initialisation window);
        afterwards ``y_t = sum_i a_i y_{t-i} + sum_j b_j f(u_{t-j}) + d`` with simulated ``y``.

        Parameters
        ----------
        u : array_like, shape (N,)
            Input of one experiment [input unit].
        y_init : array_like, shape (n_init,)
            Measured outputs ``y_0 .. y_{n_init-1}``; ``n_init >= max(na, nb - 1)`` (= ``na`` for
            the defaults) and ``n_init <= N`` [output unit].

        Returns
        -------
        numpy.ndarray, shape (N,)
            Simulated output; the first ``n_init`` entries are copies of ``y_init`` (leave them
            out when scoring).
        """
        self._check_fitted()
        u = signal("u", u)
        y_init = signal("y_init", y_init)
        n0 = y_init.size
        if n0 < self._lag or n0 > u.size:
            raise ValueError(f"y_init must hold between max(na, nb - 1) = {self._lag} and "
                             f"len(u) = {u.size} samples, got {n0}")
        out = np.empty(u.size)
        out[:n0] = y_init
        if n0 == u.size:
            return out

        den = np.concatenate(([1.0], -self.a_))
        past = y_init[::-1][:self.na]                # y_{n0-1}, y_{n0-2}, ...
        zi = lfiltic([1.0], den, past) if self.na else None
        forcing = self._forcing(u)[n0:]
        out[n0:] = lfilter([1.0], den, forcing, zi=zi)[0] if self.na else forcing
        return out

    def predict(self, u, y) -> np.ndarray:
        """One-step-ahead prediction (uses the *measured* past outputs; not a simulation).

        ``yhat_t = sum_i a_i y_{t-i} + sum_j b_j f(u_{t-j}) + d`` with measured ``y``.  Its error is
        usually far smaller than the free-run error of :meth:`simulate`; report which is which.

        Parameters
        ----------
        u, y : array_like, shape (N,)
            Input and measured output of one experiment, ``N > max(na, nb - 1)``.

        Returns
        -------
        numpy.ndarray, shape (N,)
            Predictions; the first ``max(na, nb - 1)`` entries are copies of ``y``.
        """
        self._check_fitted()
        u, y = signal("u", u), signal("y", y)
        if u.shape != y.shape:
            raise ValueError(f"u and y have different lengths ({u.size} and {y.size})")
        lag = self._lag
        if u.size <= lag:
            raise ValueError(f"need more than max(na, nb - 1) = {lag} samples, got {u.size}")
        out = y.copy()
        ar = np.zeros(u.size)
        for i, a_i in enumerate(self.a_, start=1):
            ar[i:] += a_i * y[:-i]
        out[lag:] = (ar + self._forcing(u))[lag:]
        return out
