"""The LS-SVM NARX black-box model: ``predict`` is one step ahead, ``simulate`` the free run;
automatic tuning uses the free-run simulation error on held-out data.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from certkit.ident.dynamic_model import DynamicModel, input_lags, lag_window, regression_rows
from certkit.ident.experiments import (DataInputError, experiments, free_run_folds, order,
                                       per_channel, positive_number)
from certkit.ident.fixed_size import FixedSizeLSSVM, renyi_bandwidth, select_prototypes
from certkit.ident.free_run import low_pass, narx_steps
from certkit.ident.lssvm import CHUNK_ENTRIES, LSSVMRegressor, kept_kernel, tune
from certkit.ident.search_space import warn_of_edges
from certkit.ident.signature import orders_positional
from certkit.ident.sizing import choose_engine

# ----------------------------------------------------------------------------- NARX
def narx_regressors(u, y, na: int, nb=2, delay=1) -> tuple[np.ndarray, np.ndarray]:
    """NARX regression rows, built inside each experiment only.

    Parameters
    ----------
    u, y : array_like or list of array_like
        Input (shape (n,) or (n, n_inputs)) and output (n,) of one experiment, or lists of
        them (pairwise of equal length).
    na : int
        Output lags.
    nb, delay : int or sequence of int
        Input lags and input delay, for every input channel or one per channel.

    Returns
    -------
    X : numpy.ndarray, shape (rows, na + Σ nb)
        Rows x_t = [y_{t−1}, …, y_{t−na}, u_{1,t−d₁}, …, u_{1,t−d₁−nb₁+1}, u_{2,t−d₂}, …].
    target : numpy.ndarray, shape (rows,)
        y_t, for t = t0 … N−1 of every experiment, t0 = max(na, d_c + nb_c − 1): a window
        never reaches into another experiment.
    """
    pairs, _ = experiments(u, y)
    n_inputs = pairs[0][0].shape[1]
    nb, delay = per_channel("nb", nb, n_inputs), per_channel("delay", delay, n_inputs)
    return regression_rows(pairs, na, nb, delay)


OUTPUT_BOUNDS = ("none", "upper", "range")
FILTER_STATE_GRID = 41      # candidate initial filter states over the training input range


def input_filter(u: np.ndarray, pole: float, z0=None, delay: int = 1,
                 cap: float = np.inf) -> np.ndarray:
    """Unit-gain first-order low-pass of one input channel, saturating at ``cap``.

    z_0 = min(z0, cap) (``z0`` default u_0: the input's steady state at the record's
    start) and z_t = min(p·z_{t−1} + (1 − p)·u_{t−d}, cap) for t ≥ 1, with u_{t−d} = u_0
    before the record starts.  A fixed filter of the input is an output-independent input
    "state", as the first Laguerre function of a Laguerre model, a first-order low-pass
    whose pole is fixed beforehand (Wahlberg, "System identification using Laguerre
    models", IEEE Trans. Automatic Control 36(5), 1991).  ``z0`` an array of k starting
    states: the k runs at once, as the columns of an (n, k) array.
    """
    u = np.asarray(u, dtype=float)
    if u.size == 0:
        return np.empty((0, np.size(z0))) if np.ndim(z0) else np.empty(0)
    starts = np.atleast_1d(np.asarray(u[0] if z0 is None else z0, dtype=float))
    z = low_pass(u, float(pole), starts, int(delay), float(cap))
    return z if np.ndim(z0) else z[:, 0]


class NARX(DynamicModel):
    """LS-SVM NARX model y_t = f(y_{t−1..t−na}, u_{c,t−d_c..t−d_c−nb_c+1}) + e_t.

    The black-box reference of the identification engines: f is an LS-SVM (dual,
    ``engine="full"``) or a fixed-size LS-SVM (``engine="fixed-size"``, for long
    records) on standardised signals.

    Parameters
    ----------
    na : int, default 2
        Number of past outputs.
    nb : int or sequence of int, default 2
        Number of past inputs, for every input channel or one per channel.
    delay : int or sequence of int, default 1
        Input delay (0 lets u_t act on y_t), for every channel or one per channel.
    gamma, sigma2 : float or None
        LS-SVM hyper-parameters (σ² in standardised regressor units).  ``None`` tunes
        that parameter by :func:`tune` on the free-run simulation error of held-out
        data (:meth:`simulation_cost`); :func:`certkit.ident.tune_free_run` tunes from
        outside and returns the cost surface.
    engine : {"full", "fixed-size", "auto"}, default "full"
        Dual LS-SVM (:class:`LSSVMRegressor`, O(N²) memory: it refuses a record whose
        kernel matrix would exceed :data:`certkit.ident.sizing.MEMORY_BUDGET`, naming the
        option that fits) or :class:`FixedSizeLSSVM` (any length).  ``"auto"``: the dual
        up to :data:`~certkit.ident.sizing.AUTO_FULL_SAMPLES` (5 000) training samples, the
        fixed-size engine above or with a parametric part; :attr:`engine_` and
        :attr:`engine_reason_` say which and why.
    prototypes : int, default 300
        Prototypes of the fixed-size engine.
    random_state : int, default 0
        Seed of the prototype selection.
    folds : int, default 3
        Folds of the internal tuning cost.
    n_init : int, optional
        Initialisation window (measured outputs) of the held-out simulations during
        tuning; default :attr:`init_length`.  At least :attr:`init_length`
        = max(na, delay + nb − 1), the lag window a free run starts from (a 10-sample
        window rules out na = 15).
    tuning : dict, optional
        Extra keyword arguments of :func:`tune` (ranges, grid, max_refine, ...).
        Default: 5 x 5 grid, γ ∈ [1e-1, 1e7], σ² ∈ [0.01·d, 1000·d] with d = na + Σnb
        (lagged samples of an oversampled signal are strongly correlated, so the useful
        σ² can be far above d: about 80·d on Silverbox).
    filter_pole : float in (0, 1), optional
        Adds one regressor per input channel: z_t, a unit-gain first-order low-pass of the
        input (:func:`input_filter`, z_t = p·z_{t−1} + (1 − p)·u_{t−d}), a proxy of a slow
        state the lagged signals show only through noise (the upper tank's level in the
        Cascaded Tanks).  The pole is a structure choice: search it with
        :func:`certkit.ident.tune_free_run` (``orders={"filter_pole": [...]}``).  In
        training each experiment's filter starts at its first input; in
        :meth:`simulate` from measured ``y_init`` its start is estimated from that window
        (:meth:`_initial_filter_state`), from rest it is 0.  Default None: no filter.
    filter_cap : float in (0, 1], optional
        The filter state saturates at this quantile of its training values (a tank that
        overflows).  Default None: no saturation.
    output_bound : {"none", "upper", "range"}, default "none"
        Clip each simulated output to at most the largest training output ("upper") or to
        the training range ("range"): a saturating output y_t = sat(f(·)) fed back in the
        recursion (an overflowing tank, a saturating sensor).  A structure choice to make
        on estimation data like the others; it also keeps a free run from diverging.
    linear : bool, default False
        With ``engine="fixed-size"``: f gets an unpenalised linear part in all regressors
        (the partially linear LS-SVM, :class:`FixedSizeLSSVM` ``linear``).  Outside the
        training amplitudes the kernel part fades and the model extrapolates linearly.
    cubic : int, default 0
        With ``linear``: unpenalised cubic monomials of the first ``cubic`` output lags
        y_{t−1} … y_{t−cubic} (a Duffing spring's y³), so a stiffening or softening
        nonlinearity extrapolates beyond the training amplitudes.  At most ``na``.
    cubic_terms : {"cubes", "all"}, default "cubes"
        y_{t−i}³ only, or every degree-3 monomial of those lags.

    Attributes
    ----------
    regressor_ : LSSVMRegressor or FixedSizeLSSVM
        The fitted map f (standardised units).
    engine_ : {"full", "fixed-size"}
        The engine used.
    engine_reason_ : str
        Why (given, or what ``engine="auto"`` compared).
    gamma_, sigma2_ : float
        Hyper-parameters used (tuned or given).
    tuning_ : TuningResult or None
        Tuning record when a parameter was tuned: every evaluation, the warnings each
        raised (recorded, not shown) and the ends of the ranges the chosen point lies on
        (``edges``; a :class:`~certkit.ident.search_space.SearchEdgeWarning` says so).
    u_mean_, u_std_ : numpy.ndarray, shape (n_inputs,)
        Standardisation of the training inputs, per channel.
    y_mean_, y_std_ : float
        Standardisation of the training output.
    n_rows_ : int
        Regression rows used (all experiments).
    n_features_in_ : int
        Number of input channels.
    output_bounds_ : (float, float)
        The clipping bounds of the simulated output [output unit] (±inf: none).
    filter_cap_, u_range_ : numpy.ndarray
        Filter saturation per channel and training input range (n_inputs, 2), in
        standardised input units.

    Notes
    -----
    ``predict(u, y)`` is the one-step-ahead predictor (measured past outputs enter every
    step); :meth:`simulate` (and ``predict(u)``) the free run (only an initialisation
    window of measured outputs, or rest, then the model's own outputs).  The free-run error
    is the figure to report and to tune on; one-step errors are usually far smaller
    (Ljung 1999, §16.6: a model is validated by simulation, not by prediction).  The
    LS-SVM is that of Suykens et al. (2002), ch. 3 (dual) and §6.5 (fixed size).

    References
    ----------
    J.A.K. Suykens, T. Van Gestel, J. De Brabanter, B. De Moor, J. Vandewalle, *Least
    Squares Support Vector Machines*, World Scientific, 2002.  L. Ljung, *System
    Identification: Theory for the User*, 2nd ed., Prentice Hall, 1999.

    Examples
    --------
    >>> from certkit.ident.validation import nrmse
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

    @orders_positional()
    def __init__(self, na: int = 2, nb=2, *, delay=1,
                 gamma: float | None = None, sigma2: float | None = None,
                 engine: str = "full", prototypes: int = 300, random_state: int = 0,
                 folds: int = 3, n_init: int | None = None, tuning: dict | None = None,
                 filter_pole: float | None = None,
                 filter_cap: float | None = None, output_bound: str = "none",
                 linear: bool = False, cubic: int = 0, cubic_terms: str = "cubes"):
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
        self.filter_pole = filter_pole
        self.filter_cap = filter_cap
        self.output_bound = output_bound
        self.linear = linear
        self.cubic = cubic
        self.cubic_terms = cubic_terms

    # -- structure
    @property
    def init_length(self) -> int:
        """Samples before the first regression row: max(na, d_c + nb_c − 1)."""
        return max([self._na] + [d + n - 1 for d, n in zip(self._delay, self._nb)])

    def _check_structure(self, n_inputs: int) -> None:
        self._na = order("na", self.na)
        self._nb = per_channel("nb", self.nb, n_inputs)
        self._delay = per_channel("delay", self.delay, n_inputs)
        if self._na + sum(self._nb) == 0:
            raise DataInputError("na, nb", "expected at least one output or input lag, "
                                           "found none")
        if self.filter_pole is not None and not 0.0 < float(self.filter_pole) < 1.0:
            raise DataInputError("filter_pole", f"expected a pole in (0, 1) or None, found "
                                                f"{self.filter_pole!r}")
        if self.filter_cap is not None and (self.filter_pole is None
                                            or not 0.0 < float(self.filter_cap) <= 1.0):
            raise DataInputError("filter_cap", f"expected a quantile in (0, 1] with a "
                                               f"filter_pole, or None, found "
                                               f"{self.filter_cap!r}")
        if self.output_bound not in OUTPUT_BOUNDS:
            raise DataInputError("output_bound", f"expected one of {', '.join(OUTPUT_BOUNDS)}"
                                                 f", found {self.output_bound!r}")
        if (self.linear or self.cubic) and self.engine == "full":
            raise DataInputError("linear, cubic", f"expected engine='fixed-size' (or 'auto') "
                                                  f"for a parametric part, found "
                                                  f"{self.engine!r}")
        if order("cubic", self.cubic) > self._na:
            raise DataInputError("cubic", f"expected at most na = {self._na} output lags, "
                                          f"found {self.cubic}")

    def _choose_engine(self, ys) -> None:
        """engine_ and engine_reason_ for the training outputs ``ys``
        (:func:`certkit.ident.sizing.choose_engine`: a full engine is checked against the
        memory budget here, before any tuning or kernel matrix)."""
        self.engine_, self.engine_reason_ = choose_engine(
            "NARX", self.engine, sum(y.size for y in ys),
            sum(y.size - self.init_length for y in ys), self.prototypes,
            "a parametric part (linear, cubic) needs it" if self.linear or self.cubic
            else None)

    def _make_regressor(self, gamma, sigma2, prototypes=None):
        if self.engine_ == "full":
            return LSSVMRegressor(gamma=gamma, sigma2=sigma2)
        return FixedSizeLSSVM(gamma=gamma, sigma2=sigma2, random_state=self.random_state,
                              prototypes=self.prototypes if prototypes is None
                              else prototypes, linear=bool(self.linear), cubic=self.cubic,
                              cubic_terms=self.cubic_terms)

    # -- standardisation
    @staticmethod
    def _standardisation(us, ys):
        u_all, y_all = np.vstack(us), np.concatenate(ys)
        u_std = u_all.std(axis=0)
        return (u_all.mean(axis=0), np.where(u_std > 0, u_std, 1.0),
                float(y_all.mean()), float(y_all.std()) or 1.0)

    def _scaled(self, us, ys, scaling=None):
        u_mean, u_std, y_mean, y_std = scaling or (self.u_mean_, self.u_std_,
                                                   self.y_mean_, self.y_std_)
        return [(u - u_mean) / u_std for u in us], [(y - y_mean) / y_std for y in ys]

    def _rows(self, us, ys):
        X, target = regression_rows(list(zip(us, ys)), self._na, self._nb, self._delay)
        if self.filter_pole is None:
            return X, target
        start = self.init_length
        Z = np.vstack([self._filter_columns(u)[start:] for u in us])
        return np.hstack([X, Z]), target

    # -- input filter (standardised units: the filter has unit gain, so filtering the
    #    standardised input gives the standardised filter state)
    def _filter_columns(self, u: np.ndarray, z0=None, caps=None) -> np.ndarray:
        """(n, n_inputs) filter states of every channel of the standardised input ``u``,
        from ``z0`` (one per channel; default u_0) and saturating at ``caps``."""
        caps = self.filter_cap_ if caps is None else caps
        return np.column_stack([
            input_filter(u[:, c], float(self.filter_pole), None if z0 is None else z0[c],
                         self._delay[c], caps[c]) for c in range(u.shape[1])])

    def _initial_filter_state(self, model, u: np.ndarray, y_init: np.ndarray):
        """Filter states at sample 0 estimated from the initialisation window, like the
        lagged outputs: per channel (in turn), the value of a grid over the training input
        range whose one-step predictions of the measured y_init (rows after the lag
        window) are closest in least squares.  No such row (a window of init_length
        samples, or a run from rest): u_0."""
        n0, start = y_init.size, self.init_length
        if n0 <= start:
            return None
        X, target = regression_rows([(u[:n0], y_init)], self._na, self._nb, self._delay)
        z0 = u[0].copy()
        column = X.shape[1]                  # the first filter column of the rows
        for c in range(u.shape[1]):
            grid = np.linspace(*self.u_range_[c], FILTER_STATE_GRID)
            # the rows of every grid value at once (one kernel evaluation, not 41): the
            # other channels' states as chosen so far, channel c's from each grid value
            rows = np.tile(np.hstack([X, self._filter_columns(u[:n0], z0)[start:]]),
                           (grid.size, 1))
            states = input_filter(u[:n0, c], float(self.filter_pole), grid, self._delay[c],
                                  self.filter_cap_[c])
            rows[:, column + c] = states[start:].T.ravel()
            error = model.predict(rows).reshape(grid.size, -1) - target
            z0[c] = grid[int(np.argmin(np.einsum("ij,ij->i", error, error)))]
        return z0

    # -- fitting
    def _fit(self, pairs) -> None:
        us, ys = [p[0] for p in pairs], [p[1] for p in pairs]
        self._check_structure(us[0].shape[1])
        lag_window(pairs, self._na, self._nb, self._delay)         # shape checks first
        self._choose_engine(ys)
        scaling = self._standardisation(us, ys)
        self.u_mean_, self.u_std_, self.y_mean_, self.y_std_ = scaling
        us, ys = self._scaled(us, ys)
        self._set_bounds(us, ys)
        self.tuning_ = None
        if self.gamma is None or self.sigma2 is None:
            d = self._na + sum(self._nb)
            options = {"gamma": (1e-1, 1e7) if self.gamma is None else self.gamma,
                       "sigma2": (0.01 * d, 1e3 * d) if self.sigma2 is None
                       else self.sigma2, "grid": 5}
            options.update(self.tuning or {})
            self.tuning_ = tune(self._scaled_simulation_cost(us, ys), **options)
            warn_of_edges(list(self.tuning_.edges), "NARX's own tuning", stacklevel=5)
            self.gamma_, self.sigma2_ = self.tuning_.gamma, self.tuning_.sigma2
        else:
            self.gamma_ = positive_number("gamma", self.gamma)
            self.sigma2_ = positive_number("sigma2", self.sigma2)
        X, target = self._rows(us, ys)
        self.regressor_ = self._make_regressor(self.gamma_, self.sigma2_).fit(X, target)
        self.n_rows_ = X.shape[0]

    def _set_bounds(self, us, ys) -> None:
        """Output bound, filter caps and input range (standardised) from training data."""
        y_all = np.concatenate(ys)
        self._low = float(y_all.min()) if self.output_bound == "range" else -np.inf
        self._high = float(y_all.max()) if self.output_bound != "none" else np.inf
        self.output_bounds_ = (self._low * self.y_std_ + self.y_mean_,
                               self._high * self.y_std_ + self.y_mean_)
        n_inputs = us[0].shape[1]
        u_all = np.vstack(us)
        self.u_range_ = np.column_stack([u_all.min(axis=0), u_all.max(axis=0)])
        self.filter_cap_ = np.full(n_inputs, np.inf)
        if self.filter_pole is not None and self.filter_cap is not None:
            states = np.vstack([self._filter_columns(u) for u in us])
            self.filter_cap_ = np.quantile(states, float(self.filter_cap), axis=0)

    def simulation_cost(self, u, y) -> Callable[[float, float], float]:
        """Free-run cross-validation cost ``cost(gamma, sigma2)`` on held-out data.

        Folds by :func:`certkit.ident.experiments.free_run_folds` (whole experiments when
        there are at least ``folds``, else contiguous segments of each); each held-out
        piece is simulated in free run from its first ``n_init`` measured outputs.
        Signals are standardised with the statistics of all the data given, as in
        :meth:`fit`.

        Returns
        -------
        callable
            Mean squared free-run error after the initialisation windows, divided by
            the output variance (= NRMSE²) over all folds.
        """
        pairs, _ = experiments(u, y)
        us, ys = [p[0] for p in pairs], [p[1] for p in pairs]
        self._check_structure(us[0].shape[1])
        narx_regressors(us, ys, self._na, self._nb, self._delay)
        self._choose_engine(ys)
        scaling = self._standardisation(us, ys)
        us, ys = self._scaled(us, ys, scaling)
        self._set_bounds(us, ys)
        return self._scaled_simulation_cost(us, ys)

    def _scaled_simulation_cost(self, us, ys):
        n_init = self.init_length if self.n_init is None else order("n_init", self.n_init)
        if n_init < self.init_length:
            raise DataInputError("n_init", f"expected at least the lag window "
                                           f"{self.init_length}, found {n_init}")
        splits = free_run_folds([y.size for y in ys], self.folds,
                                n_init + self.init_length + 1)
        prepared = []
        for train, held in splits:
            X, target = self._rows([us[e][s] for e, s in train], [ys[e][s] for e, s in train])
            protos = None
            if self.engine_ == "fixed-size":    # prototypes do not depend on (γ, σ²)
                protos = X[select_prototypes(X, self.prototypes, renyi_bandwidth(X),
                                             random_state=self.random_state)]
            prepared.append((X, target, protos, [(us[e][s], ys[e][s]) for e, s in held]))

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
    def _one_step(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        X, _ = self._rows(*self._scaled([u], [y]))
        pred = y.copy()
        pred[self.init_length:] = self.regressor_.predict(X) * self.y_std_ + self.y_mean_
        return pred

    def _simulate_one(self, u: np.ndarray, y_init: np.ndarray) -> np.ndarray:
        (scaled_u,), (scaled_init,) = self._scaled([u], [y_init])
        return (self._simulate_scaled(self.regressor_, scaled_u, scaled_init) * self.y_std_
                + self.y_mean_)

    def _simulate_scaled(self, model, u: np.ndarray, y_init: np.ndarray) -> np.ndarray:
        """Recursive simulation in standardised units (u of shape (n, n_inputs)).

        The RBF kernel factorises over the regressor coordinates, so the input part
        exp(−‖u-window − c_u‖²/σ²)·α_j is computed for a block of steps at once and only
        the output-lag part is evaluated inside the recursion
        (:func:`certkit.ident.free_run.narx_steps`, compiled).
        """
        n, start, na = u.shape[0], y_init.size, self._na
        centres, coef, bias, s2 = model.support_, model.alpha_, model.b_, model.sigma2
        c_y, c_u = centres[:, :na], centres[:, na:]
        lags = input_lags(self._nb, self._delay)
        states = None
        if self.filter_pole is not None:
            states = self._filter_columns(u, self._initial_filter_state(model, u, y_init))
        low, high = self._low, self._high
        # parametric part (fixed-size engine; zero otherwise): β_y on the output lags in
        # time order, β_u on the input columns, θ on the cubic monomials of the lags
        beta = getattr(model, "linear_", np.zeros(centres.shape[1]))
        beta_y, beta_u = np.ascontiguousarray(beta[:na][::-1]), beta[na:]
        theta = getattr(model, "cubic_", np.zeros(0))
        monomials = na - 1 - getattr(model, "monomials_", np.zeros((0, 3), dtype=int))
        y = np.empty(n)
        y[:start] = y_init
        # −‖h − c_y‖²/σ² expanded; columns reversed so h = y[t−na:t] in time order
        lin = np.ascontiguousarray(2.0 * c_y[:, ::-1] / s2)
        offset = -np.sum(c_y * c_y, axis=1) / s2
        block = max(1, CHUNK_ENTRIES // (4 * centres.shape[0]))
        for first in range(start, n, block):
            t = np.arange(first, min(first + block, n))
            shift = np.full(t.size, bias)
            if lags or states is not None:
                columns = [u[t - lag, c] for c, lag in lags]
                window = np.column_stack(columns + ([] if states is None else [states[t]]))
                weights = kept_kernel(window, c_u, s2) * coef
                shift += window @ beta_u
            else:
                weights = np.broadcast_to(coef, (t.size, coef.size))
            if na == 0:
                y[t] = np.clip(weights.sum(axis=1) + shift, low, high)
                continue
            narx_steps(y, first, np.ascontiguousarray(weights), shift, lin, offset, float(s2),
                       beta_y, theta, monomials, low, high)
        return y
