"""Wiener models (a linear block, then a static nonlinearity) and the small-signal method
that finds their linear block on a plant.

Two routes to the linear block:

* the seed paper's small-signal method (§4, steps 1-10): excite the plant with a small
  random force, repeat it scaled by K, and accept linearity when the response scales by
  K within a stated tolerance, else shrink the amplitude; the linear block (ARX, orders
  of the seed: 6 poles, 4 input terms) is fitted to the accepted small-signal records;
* the best linear approximation (Schoukens & Tiels, arXiv 1607.01217): the linear model
  fitted to the plant's response to a Gaussian excitation at the operating amplitude.

Either block is scaled to unit static gain, so its output z carries the input's unit
and the static nonlinearity y = f(z) (LS-SVM regression from z to the measured output) is
the plant's quasi-static input-output curve (a gear's load-travel curve).  The plant is any
callable taking an input deviation (a force [N] in the drop protocol) and returning a dict
of output deviations; the drop protocol makes one from a gear's calibrated drop model
driven by a prescribed ground load (:mod:`certkit.gear_identification`, which uses this
module, never the reverse).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import butter, sosfiltfilt
from sklearn.utils.validation import check_is_fitted

from certkit.ident.dynamic_model import DynamicModel
from certkit.ident.experiments import DataInputError, positive_number
from certkit.ident.linear_models import ARX
from certkit.ident.fixed_size import FixedSizeLSSVM
from certkit.ident.lssvm import LSSVMRegressor, kfold_cost, tune
from certkit.ident.search_space import warn_of_edges
from certkit.ident.signature import orders_positional
from certkit.ident.sizing import choose_engine

Plant = Callable[[np.ndarray], dict]


@dataclass(frozen=True)
class LinearityStep:
    """One K-scaling check of the small-signal method."""

    amplitude: float        # RMS of the small force [N]
    mismatch: dict          # output -> ‖y_K − K·y_1‖/‖K·y_1‖
    accepted: bool


@dataclass
class SmallSignalExperiment:
    """The accepted small-signal records and the checks that led to them."""

    force: list                       # the excitations applied [N]
    responses: dict                   # output -> list of response records
    steps: list = field(default_factory=list)
    accepted: bool = False


def excitation(samples: int, sample_rate: float, bandwidth: float, seed: int) -> np.ndarray:
    """Zero-mean random force of unit RMS, low-passed to ``bandwidth`` [Hz] (a small random
    signal, step 1), starting and ending at zero."""

    rng = np.random.default_rng(seed)
    signal = sosfiltfilt(butter(4, bandwidth, fs=sample_rate, output="sos"),
                         rng.standard_normal(samples))
    taper = np.minimum(1.0, np.minimum(np.arange(samples), np.arange(samples)[::-1])
                       / (0.02 * samples))
    signal = signal * taper
    signal = signal - taper * (signal.sum() / taper.sum())   # zero mean, still 0 at the ends
    return signal / np.sqrt(np.mean(signal ** 2))


def small_signal_records(plant: Plant, outputs: list[str], samples: int, sample_rate: float,
                         amplitude: float, gain: float = 2.0, tolerance: float = 0.05,
                         shrink: float = 0.5, max_steps: int = 8, bandwidth: float = 30.0,
                         seed: int = 0) -> SmallSignalExperiment:
    """Steps 1-4: find an amplitude at which the plant responds linearly.

    Applies ``amplitude``·r and ``gain``·``amplitude``·r (r: :func:`excitation`) and
    checks that every output scales by ``gain`` within ``tolerance``.  While it does, the
    amplitude grows by ``gain`` and the largest linear one is kept (steps 2-3); if the
    first check fails the amplitude shrinks by ``shrink`` until one passes (step 4); at
    most ``max_steps`` checks.
    """
    base = excitation(samples, sample_rate, bandwidth, seed)
    experiment = SmallSignalExperiment(force=[], responses={name: [] for name in outputs})

    def check(level: float):
        first, second = level * base, gain * level * base
        y1, y2 = plant(first), plant(second)
        mismatch = {}
        for name in outputs:
            reference = gain * y1[name]
            norm = float(np.linalg.norm(reference))
            mismatch[name] = (float(np.linalg.norm(y2[name] - reference)) / norm
                              if norm > 0 else float("inf"))
        accepted = all(m <= tolerance for m in mismatch.values())
        experiment.steps.append(LinearityStep(level, mismatch, accepted))
        return accepted, (first, second, y1, y2)

    def keep(records) -> None:
        first, second, y1, y2 = records
        experiment.force = [first, second]
        experiment.responses = {name: [y1[name], y2[name]] for name in outputs}
        experiment.accepted = True

    accepted, records = check(amplitude)
    if accepted:
        # steps 2-3: while the response stays linear, apply the scaled signal again; keep
        # the largest amplitude that was still linear
        for _ in range(max_steps - 1):
            keep(records)
            amplitude *= gain
            accepted, records = check(amplitude)
            if not accepted:
                return experiment
        keep(records)
        return experiment
    # step 4: not linear: bring the amplitude back within the margin until it is
    for _ in range(max_steps - 1):
        amplitude *= shrink
        accepted, records = check(amplitude)
        if accepted:
            keep(records)
            return experiment
    return experiment


def best_linear_records(plant: Plant, outputs: list[str], samples: int, sample_rate: float,
                        amplitude: float, realisations: int = 2, bandwidth: float = 30.0,
                        seed: int = 100) -> SmallSignalExperiment:
    """Records for the best linear approximation: Gaussian-like excitations at the
    operating amplitude (several realisations), no linearity check."""
    experiment = SmallSignalExperiment(force=[], responses={name: [] for name in outputs},
                                       accepted=True)
    for index in range(realisations):
        force = amplitude * excitation(samples, sample_rate, bandwidth, seed + index)
        response = plant(force)
        experiment.force.append(force)
        for name in outputs:
            experiment.responses[name].append(response[name])
    return experiment


def static_map(z: np.ndarray, y: np.ndarray, gamma: float | None = None,
               sigma2: float | None = None, target: float = 0.0, *, engine: str = "full",
               prototypes: int = 100, random_state: int = 0
               ) -> LSSVMRegressor | FixedSizeLSSVM:
    """The static map y = f(z) of a Wiener model (the seed's steps 8-9): an LS-SVM regression,
    (γ, σ²) as given or tuned by 4-fold cross-validation on a shuffled (seeded) subsample of
    300 samples: a 5 x 5 log grid (γ ∈ [1, 1e7], σ² ∈ [1e-3, 10]·var(z)), then a Nelder-Mead
    refinement only while the cross-validated RMSE is above ``target`` [units of y].  The
    subsample is fitted by the exact dual whatever ``engine`` fits the whole record.

    Returns
    -------
    LSSVMRegressor or FixedSizeLSSVM
        Fitted on all samples of ``z`` (n,) and ``y`` (n,): the dual (``engine="full"``)
        or the fixed-size LS-SVM on ``prototypes`` points of z.
    """
    z = np.asarray(z, dtype=float).reshape(-1, 1)
    if gamma is None or sigma2 is None:
        order = np.random.default_rng(0).permutation(z.shape[0])[:300]
        scale = float(np.var(z)) or 1.0
        cost = kfold_cost(lambda g, s: LSSVMRegressor(gamma=g, sigma2=s), z[order], y[order],
                          folds=4)
        ranges = {"gamma": gamma if gamma else (1e0, 1e7),
                  "sigma2": sigma2 if sigma2 else (1e-3 * scale, 10 * scale)}
        result = tune(cost, grid=5, refine=False, **ranges)
        if np.sqrt(result.cost) > target:
            start = (result.gamma, result.sigma2)
            result = tune(cost, grid=5, start=start, max_refine=15, **ranges)
        warn_of_edges(list(result.edges), "WienerLSSVM's static map", stacklevel=5)
        gamma, sigma2 = result.gamma, result.sigma2
    if engine == "full":
        return LSSVMRegressor(gamma=gamma, sigma2=sigma2).fit(z, y)
    return FixedSizeLSSVM(gamma=gamma, sigma2=sigma2, prototypes=prototypes,
                          random_state=random_state).fit(z, y)


class WienerLSSVM(DynamicModel):
    """Wiener model: a linear block (ARX, unit static gain) then a static LS-SVM map.

    z_t = G(q)·u_t (unit static gain from input channel 0; several channels add up in z),
    y_t = f(z_t) + e_t.

    Two routes to the linear block:

    * **from the recorded data** (``linear_block=None``): the best linear approximation,
      an ARX with intercept fitted on the same u, y (Schoukens & Tiels, arXiv 1607.01217),
      then f on z — one call to :meth:`fit`;
    * **given** (``linear_block=`` a fitted :class:`ARX`): e.g. the seed paper's
      small-signal method (§4 steps 1-5: :func:`small_signal_records` on a plant, then
      ``ARX(...).fit`` on its records); :meth:`fit` then only identifies f (steps 6-9).
      ``sklearn.base.clone`` re-creates estimator parameters unfitted: wrap the block in
      ``sklearn.frozen.FrozenEstimator`` to keep it through ``clone``.

    Parameters
    ----------
    na : int, default 6
        Past z of the linear block (ignored with a given block).
    nb : int or sequence of int, default 4
        Input terms per channel of the linear block (ignored with a given block).
    delay : int or sequence of int, default 0
        Input delay of the linear block (ignored with a given block).
    gamma, sigma2 : float or None
        LS-SVM hyper-parameters of f; σ² in units of (z/s)² with s the ``input_scale``
        (standardised z by default).  None: tuned by :func:`static_map` (cross-validated
        static fit); :func:`certkit.ident.tune_free_run` tunes on the free run instead.
    engine : {"full", "fixed-size", "auto"}, default "full"
        f by the dual LS-SVM over every training sample of z (O(N²) memory: it refuses N
        whose kernel matrix would exceed :data:`certkit.ident.sizing.MEMORY_BUDGET`,
        naming the option that fits) or by :class:`FixedSizeLSSVM` on ``prototypes``
        points (any N).  ``"auto"``: the dual up to
        :data:`~certkit.ident.sizing.AUTO_FULL_SAMPLES` (5 000) samples, the fixed-size
        LS-SVM above; ``engine_`` and ``engine_reason_`` say which and why.
    prototypes : int, default 100
        Prototypes of the fixed-size engine (z is one-dimensional: 100 cover its range).
    random_state : int, default 0
        Seed of the prototype selection.
    linear_block : ARX or None
        A fitted linear block to use as it is, or None to fit one on the data.
    input_scale : float or None, default None
        Scale s of z in the kernel: None, the standard deviation of z over the training
        data; 1.0 puts σ² in the input's units squared.
    tuning : dict, optional
        Keyword arguments of :func:`static_map` when γ or σ² is tuned (``target``).

    Attributes
    ----------
    raw_linear_ : ARX
        The linear block as fitted (or given), gain included.
    linear_ : ARX
        The same dynamics with unit static gain, no intercept: z carries the input's unit.
    nonlinearity_ : LSSVMRegressor or FixedSizeLSSVM
        f, from z/s to y.
    engine_ : {"full", "fixed-size"}
        The engine of f.
    engine_reason_ : str
        Why (given, or what ``engine="auto"`` compared).
    input_scale_ : float
        s.
    z_range_ : (float, float)
        Range of z over the training data (where f is supported by data).
    n_features_in_ : int
        Number of input channels.

    Notes
    -----
    ``predict(u)`` and :meth:`simulate` are the free run; a Wiener model has no one-step
    predictor from past outputs (its error enters after the nonlinearity), so
    ``predict(u, y)`` is refused.  ``simulate(u, y_init)`` starts the linear block from z
    values that reproduce ``y_init`` through f (the nearest point of f on a fine grid over
    the training range of z): exact where f is monotonic, a choice of branch where not.
    The LS-SVM is that of Suykens et al. (2002), ch. 3.

    References
    ----------
    J. Schoukens, K. Tiels, "Identification of block-oriented nonlinear systems starting
    from linear approximations: a survey", Automatica 85 (2017) 272-292 (arXiv
    1607.01217).  J.A.K. Suykens et al., *Least Squares Support Vector Machines*, World
    Scientific, 2002.
    """

    @orders_positional()
    def __init__(self, na: int = 6, nb=4, *, delay=0, gamma: float | None = None,
                 sigma2: float | None = None, engine: str = "full", prototypes: int = 100,
                 random_state: int = 0, linear_block=None, input_scale=None,
                 tuning: dict | None = None):
        self.na = na
        self.nb = nb
        self.delay = delay
        self.gamma = gamma
        self.sigma2 = sigma2
        self.engine = engine
        self.prototypes = prototypes
        self.random_state = random_state
        self.linear_block = linear_block
        self.input_scale = input_scale
        self.tuning = tuning

    @property
    def init_length(self) -> int:
        """Samples of z history the linear block needs to start a free run."""
        return self.linear_.init_length

    def _block(self, pairs) -> ARX:
        block = self.linear_block
        if block is None:
            return ARX(self.na, self.nb, delay=self.delay, fit_intercept=True).fit(
                [u for u, _ in pairs], [y for _, y in pairs])
        block = getattr(block, "estimator", block)      # a FrozenEstimator's block
        if not isinstance(block, ARX) or not hasattr(block, "a_"):
            raise DataInputError("linear_block", f"expected a fitted ARX (wrap it in "
                                 f"sklearn.frozen.FrozenEstimator to keep it through clone),"
                                 f" found {'an unfitted ' if isinstance(block, ARX) else ''}"
                                 f"{type(block).__name__}")
        if block.n_features_in_ != pairs[0][0].shape[1]:
            raise DataInputError("linear_block", f"expected a block of "
                                 f"{pairs[0][0].shape[1]} input channel(s), found "
                                 f"{block.n_features_in_}")
        return block

    def _fit(self, pairs) -> None:
        self.raw_linear_ = self._block(pairs)
        self.linear_ = self.raw_linear_.normalised()
        z = np.concatenate([self.linear_._from_rest(u) for u, _ in pairs])
        y = np.concatenate([y for _, y in pairs])
        if not np.all(np.isfinite(z)):
            raise DataInputError("u", "expected a stable linear block, found one whose "
                                      "output is not finite")
        if self.input_scale is None:
            self.input_scale_ = float(np.std(z)) or 1.0
        else:
            self.input_scale_ = positive_number("input_scale", self.input_scale)
        self.z_range_ = (float(z.min()), float(z.max()))
        gamma = None if self.gamma is None else positive_number("gamma", self.gamma)
        sigma2 = None if self.sigma2 is None else positive_number("sigma2", self.sigma2)
        self.engine_, self.engine_reason_ = choose_engine("WienerLSSVM", self.engine, z.size,
                                                          z.size, self.prototypes)
        self.nonlinearity_ = static_map(z / self.input_scale_, y, gamma, sigma2,
                                        engine=self.engine_, prototypes=self.prototypes,
                                        random_state=self.random_state,
                                        **(self.tuning or {}))

    def nonlinearity(self, z) -> np.ndarray:
        """f(z) for values of the intermediate signal z [input units]."""
        check_is_fitted(self)
        z = np.asarray(z, dtype=float)
        return self.nonlinearity_.predict(z.reshape(-1, 1) / self.input_scale_).reshape(z.shape)

    def _simulate_one(self, u: np.ndarray, y_init: np.ndarray) -> np.ndarray:
        low, high = self.z_range_
        margin = 0.1 * (high - low)
        grid = np.linspace(low - margin, high + margin, 4001)
        values = self.nonlinearity(grid)
        z_init = grid[np.argmin(np.abs(values[None, :] - y_init[:, None]), axis=1)]
        return self.nonlinearity(self.linear_._simulate_one(u, z_init))

    def _from_rest(self, u: np.ndarray) -> np.ndarray:
        return self.nonlinearity(self.linear_._from_rest(u))

    def _one_step(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        raise DataInputError("y", "a Wiener model has no one-step-ahead predictor (its error "
                                  "enters after the nonlinearity): call predict(u) or "
                                  "simulate(u, y_init)")

