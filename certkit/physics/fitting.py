"""Bounded nonlinear least-squares calibration: the model-agnostic statistical core.

The caller supplies a residual function of the physical (SI) parameter values that returns
the stacked, already-normalised residual vector (for example (simulated − measured)/σ over
all channels and runs); :func:`fit` minimises its sum of squares within the parameter
bounds (``scipy.optimize.least_squares``, trust-region reflective) and reports what the data
do and do not determine: standard errors, correlations and plain-English identifiability
warnings.

Choices, each explained where it is made:

* **Sizes.** Every parameter has a size (:attr:`FitParameter.size`, by default
  ``|nominal|``): the floor of its finite-difference step and the unit of its statistics
  and bound test; a caller fitting one parameter from several starts gives it one size.
* **Scaling.** The optimiser works in ``u = x/scale`` with ``scale = max(|start|, size)``,
  so a 1e6 Pa pre-charge and a 0.6 discharge coefficient both start at ``|u| <= 1`` (the
  solver's step test is relative to ``‖u‖``: a unit far below a start would loosen it for
  every parameter).  A linear map keeps linear models linear, allows parameters that are
  zero or change sign, and keeps the bounds simple boxes; physical values are clipped into
  their bounds, so the bounds are respected exactly.
* **Finite differences** (when no analytic Jacobian is given): central differences with
  the step ``relative_step·max(|x|, size)``, one-sided second-order stencils next to a
  bound so no residual is ever evaluated outside the bounds; with ``residuals_many`` all
  stencil points go to the simulator in one batched call (:func:`jacobian_at` at any x).
* **Statistics**: from the SVD of ``∂r/∂ln x`` (dimensionless); singular values below
  :func:`singular_cutoff` times the largest count as combinations not determined.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from numbers import Real

import numpy as np
from scipy.optimize import least_squares

from certkit.display import number
from certkit.errors import CampaignError

# A direction in log-parameter space whose singular value is below this fraction of the
# largest is "not determined" (the floor of :func:`singular_cutoff`): its standard error
# would be 1e6 times the best determined one's, while central differences over the default
# step resolve singular values down to about eps^(2/3) ≈ 4e-11 of the largest.
SINGULAR_CUTOFF = 1e-6
# The cutoff over the truncation error (h² central, h forward): a ratio x/y differenced
# over h leaves a singular value of order h² or h, not zero.
TRUNCATION_MARGIN = 10.0
# A parameter is involved in an undetermined direction when at least this share of the
# direction's squared length (in log-parameter space) lies on it: |component| >= 0.01.
NULL_SHARE = 1e-4
CORRELATION_LIMIT = 0.95   # |r| above this earns a correlation warning
BOUND_TOLERANCE = 1e-6     # relative distance within which a parameter is "on" its bound
# Central differences: truncation O(h²) against rounding O(eps/h) balance at h = eps^(1/3).
DEFAULT_RELATIVE_STEP = float(np.finfo(float).eps ** (1.0 / 3.0))

Residuals = Callable[[np.ndarray], np.ndarray]


class FitError(CampaignError, ValueError):
    """The residuals could not be evaluated (non-finite or wrong shape) at some parameter
    values; ``evaluations``: the parameter sets the failed fit had evaluated (0 outside one)."""

    evaluations: int = 0


@dataclass(frozen=True)
class FitParameter:
    """A parameter to calibrate: its name, SI unit, starting value and bounds (SI).

    Raises
    ------
    ValueError
        If a value is not finite, ``lower >= upper`` or the nominal lies outside the bounds;
        the message names the parameter.
    """

    name: str      # e.g. "orifice C_d"
    unit: str      # SI unit string, e.g. "Pa"
    nominal: float  # starting value (SI), within the bounds
    lower: float
    upper: float
    #: the parameter's size (SI, > 0): the floor of its finite-difference step and the unit
    #: of its statistics; None gives |nominal|, or the larger bound magnitude for a zero
    #: nominal.  ``dataclasses.replace(parameter, nominal=v)`` keeps it.
    size: float | None = None

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip():
            raise ValueError(f"fit parameter name must be a non-empty string, got {self.name!r}")
        for field in ("nominal", "lower", "upper"):
            value = getattr(self, field)
            try:
                finite = math.isfinite(float(value))
            except (TypeError, ValueError):
                finite = False
            if not finite:
                raise ValueError(f"fit parameter {self.name!r}: {field} must be a finite number, "
                                 f"got {value!r}")
        if not self.lower < self.upper:
            raise ValueError(f"fit parameter {self.name!r}: lower bound {self.lower:g} must be "
                             f"below upper bound {self.upper:g}")
        if not self.lower <= self.nominal <= self.upper:
            raise ValueError(f"fit parameter {self.name!r}: nominal {self.nominal:g} lies outside "
                             f"its bounds [{self.lower:g}, {self.upper:g}]")
        size = self.size
        if size is None:
            size = abs(self.nominal) or max(abs(self.lower), abs(self.upper))
        if isinstance(size, bool) or not isinstance(size, Real) or not 0 < size < math.inf:
            raise ValueError(f"fit parameter {self.name!r}: size must be a positive finite "
                             f"number, got {size!r}")
        object.__setattr__(self, "size", float(size))

    def describe(self, value: float) -> str:
        """'name = value unit', for messages."""
        return f"{self.name} = {value:.6g} {self.unit}".rstrip()


# eq=False: the numpy fields make field-wise equality ambiguous; the arrays are read-only.
@dataclass(frozen=True, eq=False)
class FitResult:
    """Outcome of :func:`fit`.  Arrays follow the order of ``parameters``; values are SI."""

    parameters: tuple[FitParameter, ...]
    estimate: np.ndarray        # SI values at the optimum
    standard_error: np.ndarray  # sqrt(diag(s²(JᵀJ)⁻¹)), s² = RSS/(m − p); nan where undetermined
    correlation: np.ndarray     # p × p; nan rows/columns where undetermined
    cost_nominal: float         # RMS of the residual vector at the nominal values
    cost: float                 # RMS of the residual vector at the optimum
    at_bound: tuple[str, ...]   # parameters on (within 1e-6 relative of) a bound
    warnings: tuple[str, ...]   # plain-English identifiability warnings
    evaluations: int            # parameter sets evaluated, Jacobian points included
    success: bool
    message: str


def fit(residuals: Residuals, parameters: Sequence[FitParameter], *,
        residuals_many: Callable[[np.ndarray], np.ndarray] | None = None,
        jacobian: Callable[[np.ndarray], np.ndarray] | None = None,
        max_evaluations: int = 100, tolerance: float = 1e-8,
        relative_step: float = DEFAULT_RELATIVE_STEP,
        differences: str = "central") -> FitResult:
    """Fit parameters to data by bounded nonlinear least squares.

    Parameters
    ----------
    residuals
        ``residuals(x) -> r``: SI parameter values (length p) to the stacked, normalised
        residual vector (length m, the same every call).
    parameters
        The parameters to fit, in the order of ``x``.
    residuals_many
        Optional ``residuals_many(X) -> R``: X of shape (k, p) to R of shape (k, m), for a
        simulator that evaluates many parameter sets at once (a Jacobian: one call).
    jacobian
        Optional analytic ``jacobian(x) -> J``, J[i, j] = ∂r_i/∂x_j in physical units, shape
        (m, p).  Replaces the finite differences (and ``residuals_many``).
    max_evaluations
        Limit on the optimiser's residual evaluations (``max_nfev``; Jacobian points are
        not counted against it).
    tolerance
        ``ftol``, ``xtol`` and ``gtol`` of ``least_squares``.
    relative_step
        Finite-difference step, a share of ``max(|x|, size)``: the default ``eps^(1/3)`` ≈
        6e-6 suits residuals exact to rounding; residuals smooth only between kinks (a
        fixed-step integration of switching force laws) need a step longer than their spacing.
    differences
        The fit's Jacobians: "central" (second order, 2·p points) or "forward" (first
        order, p + 1 points evaluated in one call, so a simulator choosing its step per call
        differences one discretisation): enough to find a fit compared with others at a
        tolerance far above its truncation error, at half the cost.  The statistics at the
        optimum come from central differences either way.

    Returns
    -------
    FitResult

    Notes
    -----
    The statistics are the Gauss-Newton linearisation at the optimum (a parameter on a bound
    keeps its unconstrained standard error, and a warning).  "Only the product/ratio is
    determined" is read from the null direction of ∂r/∂ln x there: a local statement.

    Raises
    ------
    ValueError
        For bad parameters (named in the message) or settings.
    FitError
        If the residuals are not finite, or have the wrong shape, at some parameter values
        (named in the message).
    """
    parameters = tuple(parameters)
    _check_parameters(parameters)
    if int(max_evaluations) < 1:
        raise ValueError(f"max_evaluations must be at least 1, got {max_evaluations}")
    if not tolerance > 0:
        raise ValueError(f"tolerance must be positive, got {tolerance}")
    if not 0 < relative_step < 1:
        raise ValueError(f"relative_step must lie in (0, 1), got {relative_step}")
    if differences not in ("central", "forward"):
        raise ValueError(f"differences must be 'central' or 'forward', got {differences!r}")

    problem = _ScaledProblem(parameters, residuals, residuals_many, jacobian, relative_step,
                             differences == "forward")
    try:
        u0 = problem.nominal / problem.scale
        r0 = problem.residuals(u0)
        solution = least_squares(problem.residuals, u0, jac=problem.jacobian,
                                 bounds=(problem.lower_u, problem.upper_u), method="trf",
                                 x_scale=1.0, ftol=tolerance, xtol=tolerance, gtol=tolerance,
                                 max_nfev=int(max_evaluations))
        estimate = problem.physical(solution.x)
        r = problem.residuals(solution.x)
        jac_x = problem.statistics_jacobian(solution.x) / problem.scale   # back to ∂r/∂x
    except CampaignError as error:   # a FitError, or the caller's (a simulation failed)
        error.evaluations = problem.evaluations
        raise
    cutoff = 0.0 if jacobian is not None else singular_cutoff(relative_step)
    standard_error, correlation, undetermined = _statistics(jac_x, r, estimate, problem.size,
                                                            max(cutoff, SINGULAR_CUTOFF))

    at_bound, bound_warnings = _bound_report(parameters, estimate, problem.size)
    warnings = (_undetermined_warnings(parameters, undetermined, jacobian is None)
                + _correlation_warnings(parameters, correlation)
                + bound_warnings)
    if r.size <= len(parameters):
        warnings.append(f"There are {r.size} residual(s) for {len(parameters)} parameters: "
                        "no degrees of freedom are left to estimate the noise, so no standard "
                        "errors are given.")

    for array in (estimate, standard_error, correlation):
        array.setflags(write=False)
    return FitResult(parameters=parameters, estimate=estimate, standard_error=standard_error,
                     correlation=correlation, cost_nominal=_rms(r0), cost=_rms(r),
                     at_bound=at_bound, warnings=tuple(warnings),
                     evaluations=problem.evaluations, success=bool(solution.success),
                     message=_stop_reason(solution.status, tolerance, int(max_evaluations)))


def singular_cutoff(relative_step: float, differences: str = "central") -> float:
    """The share of the largest singular value of ∂r/∂ln x below which a direction counts
    as not determined, for a Jacobian differenced over ``relative_step``: the truncation
    error (h² central, h forward) times :data:`TRUNCATION_MARGIN`, never below
    :data:`SINGULAR_CUTOFF`: differences cannot tell a weaker direction from an exact
    degeneracy (:func:`fit`'s statistics are always central: 9e-5 over 3e-3)."""
    if differences not in ("central", "forward"):
        raise ValueError(f"differences must be 'central' or 'forward', got {differences!r}")
    truncation = relative_step ** 2 if differences == "central" else relative_step
    return max(SINGULAR_CUTOFF, TRUNCATION_MARGIN * truncation)


def jacobian_at(residuals_many: Callable[[np.ndarray], np.ndarray],
                parameters: Sequence[FitParameter], x, *,
                relative_step: float = DEFAULT_RELATIVE_STEP) -> np.ndarray:
    """∂r/∂x at the SI values ``x`` (clipped into the bounds) by :func:`fit`'s central
    differences, in one ``residuals_many`` call; a :class:`FitError` if a residual is bad."""
    parameters = tuple(parameters)
    _check_parameters(parameters)
    x = np.asarray(x, dtype=float)
    if x.shape != (len(parameters),):
        raise ValueError(f"x has shape {x.shape} for {len(parameters)} parameters")
    if not 0 < relative_step < 1:
        raise ValueError(f"relative_step must lie in (0, 1), got {relative_step}")
    at = tuple(replace(p, nominal=float(min(max(v, p.lower), p.upper)))
               for p, v in zip(parameters, x, strict=True))
    problem = _ScaledProblem(at, lambda v: residuals_many(np.asarray(v)[None, :])[0],
                             residuals_many, None, relative_step)
    return problem.jacobian(problem.nominal / problem.scale) / problem.scale


def _stop_reason(status: int, tolerance: float, max_evaluations: int) -> str:
    """Why the trust-region solver stopped, in words (scipy.optimize.least_squares's
    status codes)."""
    limit = number(tolerance, 1)
    reasons = {
        0: f"stopped at the limit of {max_evaluations} model evaluations, not converged.",
        1: f"converged: the scaled gradient fell below {limit}.",
        2: f"converged: the last step changed the cost by less than {limit} of it.",
        3: f"converged: the last step changed the parameters by less than {limit} of their size.",
        4: f"converged: the last step changed both the cost and the parameters by less than "
           f"{limit} of their size."}
    return reasons.get(status, f"stopped with solver status {status}, not converged.")


# --------------------------------------------------------------------------- the scaled problem
class _ScaledProblem:
    """The residuals and their Jacobian in scaled variables u = x/scale, with evaluation
    counting, one-entry caches and checks that every residual is finite."""

    def __init__(self, parameters, residuals, residuals_many, jacobian, relative_step,
                 forward: bool = False):
        self.parameters = parameters
        self.nominal = np.array([p.nominal for p in parameters], dtype=float)
        self.lower = np.array([p.lower for p in parameters], dtype=float)
        self.upper = np.array([p.upper for p in parameters], dtype=float)
        self.size = np.array([p.size for p in parameters], dtype=float)
        # the solver's unit: where the parameter starts, at least its size (> 0)
        self.scale = np.maximum(np.abs(self.nominal), self.size)
        self.lower_u = self.lower / self.scale
        self.upper_u = self.upper / self.scale
        self._residuals = residuals
        self._residuals_many = residuals_many
        self._jacobian = jacobian
        self.relative_step = relative_step
        self.forward = forward
        self.evaluations = 0
        self.length = None          # m, fixed by the first evaluation
        self._last_r = (None, None)  # (u, r) of the latest single evaluation
        self._last_j = (None, None)  # (u, J) of the latest Jacobian

    def physical(self, u: np.ndarray) -> np.ndarray:
        """SI values; the clip removes rounding past a bound, so bounds hold exactly."""
        return np.clip(np.asarray(u, dtype=float) * self.scale, self.lower, self.upper)

    def residuals(self, u: np.ndarray) -> np.ndarray:
        cached_u, cached_r = self._last_r
        if cached_u is not None and np.array_equal(cached_u, u):
            return cached_r
        x = self.physical(u)
        self.evaluations += 1
        r = self._checked(np.array(self._residuals(x.copy()), dtype=float), x)
        r.setflags(write=False)   # cached: shared with least_squares and the Jacobian
        self._last_r = (np.array(u, dtype=float), r)
        return r

    def jacobian(self, u: np.ndarray) -> np.ndarray:
        cached_u, cached_j = self._last_j
        if cached_u is not None and np.array_equal(cached_u, u):
            return cached_j
        if self._jacobian is not None:
            x = self.physical(u)
            jac_x = np.asarray(self._jacobian(x.copy()), dtype=float)
            if jac_x.shape != (self.length, self.nominal.size) or not np.all(np.isfinite(jac_x)):
                raise FitError(f"the Jacobian must be finite with shape ({self.length}, "
                               f"{self.nominal.size}); got shape {jac_x.shape} at "
                               f"{self._describe(x)}")
            jac = jac_x * self.scale   # chain rule: ∂r/∂u = ∂r/∂x · scale
        else:
            jac = self._difference_jacobian(np.asarray(u, dtype=float))
        jac.setflags(write=False)   # cached
        self._last_j = (np.array(u, dtype=float), jac)
        return jac

    def statistics_jacobian(self, u: np.ndarray) -> np.ndarray:
        """The statistics' Jacobian: the caller's, or central differences even after a forward
        fit (a first-order error of order h would hide directions weaker than about 10·h)."""
        if self._jacobian is not None or not self.forward:
            return self.jacobian(u)
        return self._difference_jacobian(np.asarray(u, dtype=float), forward=False)

    def _difference_jacobian(self, u: np.ndarray, forward: bool | None = None) -> np.ndarray:
        """Second-order (central) differences over ``relative_step·max(|x|, size)``, the
        one-sided three-point formula (also O(h²)) where u ± h would cross a bound; or,
        ``forward`` (default: the fit's), first-order ones."""
        p = u.size
        h = self.relative_step * np.maximum(np.abs(u), self.size / self.scale)
        h = np.minimum(h, (self.upper_u - self.lower_u) / 4)  # a stencil always fits the box
        if self.forward if forward is None else forward:
            return self._forward_jacobian(u, h)
        central = (u - h >= self.lower_u) & (u + h <= self.upper_u)
        forward = ~central & (u + 2 * h <= self.upper_u)
        # stencil offsets per parameter: central (−h, +h), forward (+h, +2h), backward (−h, −2h)
        first = np.where(central | ~forward, -h, h)
        second = np.where(central, h, np.where(forward, 2 * h, -2 * h))

        points = np.repeat(u[None, :], 2 * p, axis=0)
        points[2 * np.arange(p), np.arange(p)] += first
        points[2 * np.arange(p) + 1, np.arange(p)] += second
        cached_u, base = self._last_r
        need_base = not np.all(central) and not (cached_u is not None
                                                 and np.array_equal(cached_u, u))
        if need_base:
            points = np.vstack([points, u])
        values = self._evaluate_rows(points)
        if need_base:
            base = values[-1]

        jac = np.empty((self.length, p))
        for j in range(p):
            f1, f2 = values[2 * j], values[2 * j + 1]
            if central[j]:
                jac[:, j] = (f2 - f1) / (2 * h[j])
            elif forward[j]:
                jac[:, j] = (-3 * base + 4 * f1 - f2) / (2 * h[j])
            else:
                jac[:, j] = (3 * base - 4 * f1 + f2) / (2 * h[j])
        return jac

    def _forward_jacobian(self, u: np.ndarray, h: np.ndarray) -> np.ndarray:
        """First-order differences, a step towards the inside of the box per parameter;
        the base point is evaluated in the same call as the steps (one discretisation)."""
        p = u.size
        step = np.where(u + h <= self.upper_u, h, -h)
        points = np.repeat(u[None, :], p + 1, axis=0)
        points[np.arange(p), np.arange(p)] += step
        values = self._evaluate_rows(points)
        return (values[:p] - values[p]).T / step

    def _evaluate_rows(self, points_u: np.ndarray) -> np.ndarray:
        """Residuals at each row of ``points_u``: one ``residuals_many`` call if available."""
        xs = np.array([self.physical(u) for u in points_u])
        if self._residuals_many is None:
            rows = []
            for x in xs:    # counted one by one: a failure part-way counts what was evaluated
                self.evaluations += 1
                rows.append(self._checked(np.asarray(self._residuals(x.copy()), dtype=float), x))
            return np.array(rows)
        self.evaluations += len(xs)
        values = np.asarray(self._residuals_many(xs.copy()), dtype=float)
        if self.length is None and values.ndim == 2 and values.shape[1] > 0:
            self.length = values.shape[1]
        if values.shape != (len(xs), self.length):
            expected = f"({len(xs)}, {self.length})" if self.length else \
                f"({len(xs)}, m), one row of m > 0 residuals per parameter set"
            raise FitError(f"residuals_many returned shape {values.shape} for {len(xs)} "
                           f"parameter sets; expected {expected}")
        for x, row in zip(xs, values, strict=True):
            self._checked(row, x)
        return values

    def _checked(self, r: np.ndarray, x: np.ndarray) -> np.ndarray:
        if r.ndim != 1 or r.size == 0:
            raise FitError(f"the residuals must be a non-empty 1-D array; got shape {r.shape} "
                           f"at {self._describe(x)}")
        if self.length is None:
            self.length = r.size
        elif r.size != self.length:
            raise FitError(f"the residual vector changed length from {self.length} to {r.size} "
                           f"at {self._describe(x)}")
        if not np.all(np.isfinite(r)):
            bad = int(np.count_nonzero(~np.isfinite(r)))
            raise FitError(f"{bad} of {r.size} residuals are not finite at {self._describe(x)}")
        return r

    def _describe(self, x: np.ndarray) -> str:
        return ", ".join(p.describe(v) for p, v in zip(self.parameters, x, strict=True))


# --------------------------------------------------------------------------- statistics
@dataclass(frozen=True)
class _Undetermined:
    """A group of parameters coupled by undetermined directions (indices into parameters)."""

    members: tuple[int, ...]
    dimension: int               # how many independent combinations are undetermined
    exponents: np.ndarray | None  # the one determined combination Π x_i^c_i, if exactly one


def _statistics(jac_x: np.ndarray, r: np.ndarray, estimate: np.ndarray, size: np.ndarray,
                cutoff: float = SINGULAR_CUTOFF):
    """Standard errors, correlation and undetermined groups from the Jacobian at the optimum.

    The SVD is taken of G = ∂r/∂ln x = J·diag(x) (the size replaces a zero value), which is
    dimensionless, so one relative cutoff serves all parameters and the right singular
    vectors of tiny singular values read directly as exponents of invariant products.
    Covariance: s²(JᵀJ)⁺ = D·V Σ⁻² Vᵀ·D over the determined directions, D = diag(x).
    """
    m, p = jac_x.shape
    d = np.where(estimate != 0.0, estimate, size)
    _, sigma, vt = np.linalg.svd(jac_x * d, full_matrices=m < p)
    sigma = np.concatenate([sigma, np.zeros(p - sigma.size)])
    v = vt.T
    determined = sigma > cutoff * sigma[0]   # all False if r ignores every parameter
    null = v[:, ~determined]
    projector = null @ null.T   # onto the undetermined directions (basis independent)
    undetermined = np.diag(projector) > NULL_SHARE

    v_det = v[:, determined]
    unit_cov = (v_det / sigma[determined] ** 2) @ v_det.T * np.outer(d, d)  # (JᵀJ)⁺
    variance = np.where(undetermined, np.nan, np.diag(unit_cov))
    s2 = float(r @ r) / (m - p) if m > p else np.nan
    standard_error = np.sqrt(s2 * variance)
    with np.errstate(invalid="ignore", divide="ignore"):
        root = np.sqrt(variance)
        correlation = unit_cov / np.outer(root, root)
    np.fill_diagonal(correlation, np.where(undetermined, np.nan, 1.0))
    return standard_error, correlation, _groups(projector, undetermined)


def _groups(projector: np.ndarray, undetermined: np.ndarray) -> list[_Undetermined]:
    """Connected groups of undetermined parameters (coupled when |P_ij| > NULL_SHARE)."""
    remaining = [int(i) for i in np.flatnonzero(undetermined)]
    groups = []
    while remaining:
        members, frontier = [], [remaining.pop(0)]
        while frontier:
            i = frontier.pop()
            members.append(i)
            linked = [j for j in remaining if abs(projector[i, j]) > NULL_SHARE]
            remaining = [j for j in remaining if j not in linked]
            frontier.extend(linked)
        members.sort()
        block = projector[np.ix_(members, members)]
        dimension = round(float(np.trace(block)))
        exponents = None
        if len(members) - dimension == 1:
            # the determined combination spans the rest of the group's log-space
            _, vectors = np.linalg.eigh(np.eye(len(members)) - block)
            exponents = vectors[:, -1] / np.max(np.abs(vectors[:, -1]))
            if exponents[np.flatnonzero(np.abs(exponents) > 1e-3)[0]] < 0:
                exponents = -exponents
        groups.append(_Undetermined(tuple(members), dimension, exponents))
    return groups


# --------------------------------------------------------------------------- warnings
def _undetermined_warnings(parameters, groups: list[_Undetermined],
                           differenced: bool = True) -> list[str]:
    """The undetermined groups' warnings; ``differenced``: by finite differences, which
    resolve a dependence down to their truncation error only (not an analytic Jacobian)."""
    warnings = []
    for group in groups:
        names = [parameters[i].name for i in group.members]
        listed = _join(names)
        one = len(names) == 1
        nan_note = ("its standard error is" if one else
                    "their standard errors are") + " reported as nan."
        if group.dimension >= len(names):
            how = ("change with it by less than the fit's finite differences resolve" if one
                   else "change with them by less than the fit's finite differences resolve")
            if not differenced:
                how = f"do not depend on {'it' if one else 'them'}"
            warnings.append(f"{listed} {'is' if one else 'are'} not determined by "
                            f"the data: the residuals {how}; {nan_note}")
        elif group.exponents is not None:
            kind, expression = _combination(names, group.exponents)
            unchanged = ("changing the residuals by more than the fit's finite differences "
                         "resolve" if differenced else "changing the residuals")
            warnings.append(f"Only the {kind} {expression} is determined by the data: {listed} "
                            f"can change together, keeping {expression} fixed, without "
                            f"{unchanged}; {nan_note}")
        else:
            count = ("one combination of them is" if group.dimension == 1
                     else f"{group.dimension} independent combinations of them are")
            warnings.append(f"The data do not determine {listed} separately: {count} not "
                            f"determined; {nan_note}")
    return warnings


def _combination(names: list[str], exponents: np.ndarray) -> tuple[str, str]:
    """('product', 'A·B'), ('ratio', 'A/B') or ('combination', 'A^1·B^-0.5')."""
    if np.all(np.abs(np.abs(exponents) - 1.0) < 0.05):
        top = [n for n, c in zip(names, exponents, strict=True) if c > 0]
        bottom = [n for n, c in zip(names, exponents, strict=True) if c < 0]
        if not bottom:
            return "product", "·".join(top)
        denominator = bottom[0] if len(bottom) == 1 else "(" + "·".join(bottom) + ")"
        kind = "ratio" if len(top) == 1 and len(bottom) == 1 else "combination"
        return kind, f"{'·'.join(top)}/{denominator}"
    terms = [n if abs(c - 1.0) < 1e-3 else f"{n}^{c:.3g}"
             for n, c in zip(names, exponents, strict=True) if abs(c) > 1e-3]
    return "combination", "·".join(terms)


def _correlation_warnings(parameters, correlation: np.ndarray) -> list[str]:
    warnings = []
    p = len(parameters)
    for i in range(p):
        for j in range(i + 1, p):
            r = correlation[i, j]
            if np.isfinite(r) and abs(r) > CORRELATION_LIMIT:
                warnings.append(f"{parameters[i].name} and {parameters[j].name} are strongly "
                                f"correlated (r = {r:.3f}): the data determine a combination of "
                                "them better than each one.")
    return warnings


def _bound_report(parameters, estimate: np.ndarray, sizes: np.ndarray):
    at_bound, warnings = [], []
    for parameter, value, size in zip(parameters, estimate, sizes, strict=True):
        for side, bound in (("lower", parameter.lower), ("upper", parameter.upper)):
            if abs(value - bound) <= BOUND_TOLERANCE * max(abs(bound), size):
                at_bound.append(parameter.name)
                warnings.append(f"{parameter.name} ended on its {side} bound "
                                f"({value:.6g} {parameter.unit}".rstrip() +
                                "): the bound, not the data, decides it.")
                break
    return tuple(at_bound), warnings


# --------------------------------------------------------------------------- helpers
def _check_parameters(parameters: tuple) -> None:
    if not parameters:
        raise ValueError("fit needs at least one FitParameter")
    for parameter in parameters:
        if not isinstance(parameter, FitParameter):
            raise TypeError(f"expected FitParameter objects, got {parameter!r}")
    names = [p.name for p in parameters]
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        raise ValueError(f"fit parameter names must be unique; repeated: {', '.join(duplicates)}")


def _join(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _rms(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(r ** 2)))
