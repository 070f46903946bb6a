"""The LS-SVM NARX black-box model: ``predict`` is one step ahead, ``simulate`` the free run;
automatic tuning uses the free-run simulation error on held-out data.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from certkit.ident.experiments import experiments
from certkit.ident.fixed_size import FixedSizeLSSVM, renyi_bandwidth, select_prototypes
from certkit.ident.lssvm import CHUNK_ENTRIES, LSSVMRegressor, positive_number, rbf_kernel, tune

# ----------------------------------------------------------------------------- NARX

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
    pairs, _ = experiments(u, y)
    us, ys = [p[0] for p in pairs], [p[1] for p in pairs]
    start = max(na, delay + nb - 1)
    blocks, targets = [], []
    for k, (ue, ye) in enumerate(zip(us, ys)):
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
    and to tune on; one-step errors are usually far smaller (Ljung 1999, §16.6: a model is
    validated by simulation, not by prediction).

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
        pairs, _ = experiments(u, y)
        us, ys = [p[0] for p in pairs], [p[1] for p in pairs]
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
            self.gamma_ = positive_number("gamma", self.gamma)
            self.sigma2_ = positive_number("sigma2", self.sigma2)
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
        pairs, _ = experiments(u, y)
        us, ys = [p[0] for p in pairs], [p[1] for p in pairs]
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
        pairs, single = experiments(u, y)
        out = []
        for ue, ye in pairs:
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
        pairs, single = experiments(u, y_init, ("u", "y_init"), same_length=False)
        us, inits = [p[0] for p in pairs], [p[1] for p in pairs]
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
        block = max(1, CHUNK_ENTRIES // (4 * centres.shape[0]))
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
