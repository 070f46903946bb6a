"""Measurement uncertainty of a measured value, and whether it conforms to a limit.

The general methods, apart from any drop test: :mod:`certkit.compliance.verdict_uncertainty`
applies them to the verdicts (its Monte Carlo summary, decision rules and conformance
probability are these; its GUM is the same law taken through the engine).  :func:`gum`,
:func:`monte_carlo` and :func:`validated` serve the worked examples of JCGM 101 in the tests.

* An input quantity (:class:`Input`) has an estimate and a probability distribution:
  normal with a standard uncertainty (a calibration certificate's expanded uncertainty U
  with its coverage factor k gives u = U/k), rectangular or triangular with a half-width
  (a tolerance, a resolution).  JCGM 100:2008 (GUM) §4.3.7 and §4.3.9 give their standard
  uncertainties: a/√3 and a/√6 for the half-width a.
* :func:`gum`: the law of propagation of uncertainty (GUM §5.1.2, eq. (10); with
  correlations §5.2.2, eq. (13)), the sensitivity coefficients c_i = ∂f/∂x_i taken
  numerically by central differences through the very function that makes the value, and
  each input's contribution c_i·u(x_i) and share of u_c²(y).
* :func:`monte_carlo`: the propagation of distributions by the Monte Carlo method (JCGM
  101:2008 §7): M draws of every input, the function evaluated on all of them at once, the
  estimate (the mean, §7.6), its standard uncertainty and the probabilistically symmetric
  coverage interval (§7.7).
* :func:`validated`: whether the GUM result is validated by the Monte Carlo one (JCGM 101
  §8.2): both coverage intervals' end points agree within the numerical tolerance δ of u(y)
  given to ``digits`` significant digits.
* :func:`conformance_probability`: the probability that the measurand lies within its
  tolerance interval, for a normal PDF of the measurand (JCGM 106:2012 §7.2–7.3).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from statistics import NormalDist

import numpy as np

DISTRIBUTIONS = ("normal", "rectangular", "triangular")


@dataclass(frozen=True)
class Input:
    """One input quantity: its estimate (SI), its distribution and the distribution's
    spread (SI): the standard uncertainty of a normal one, the half-width of a rectangular
    or triangular one (symmetric about the estimate)."""

    name: str
    value: float
    distribution: str
    spread: float

    def __post_init__(self):
        if self.distribution not in DISTRIBUTIONS:
            raise ValueError(f"{self.name}: distribution {self.distribution!r} is not one of "
                             f"{', '.join(DISTRIBUTIONS)}")
        if not (math.isfinite(self.spread) and self.spread >= 0):
            raise ValueError(f"{self.name}: the spread must be a finite number ≥ 0, "
                             f"found {self.spread!r}")

    @classmethod
    def expanded(cls, name: str, value: float, expanded: float, k: float) -> "Input":
        """A normal input from a certificate's expanded uncertainty U and coverage factor k
        (u = U/k, GUM §4.3.3)."""
        if not k > 0:
            raise ValueError(f"{name}: the coverage factor must be > 0, found {k!r}")
        return cls(name, value, "normal", expanded / k)

    @property
    def standard(self) -> float:
        """u(x): GUM §4.3.7 (rectangular, a/√3), §4.3.9 (triangular, a/√6)."""
        if self.distribution == "normal":
            return self.spread
        return self.spread / (math.sqrt(3.0) if self.distribution == "rectangular"
                              else math.sqrt(6.0))

    def draws(self, rng: np.random.Generator, trials: int) -> np.ndarray:
        """``trials`` values drawn from the input's distribution (JCGM 101 §6.4)."""
        if self.distribution == "normal":
            return self.value + self.spread * rng.standard_normal(trials)
        if self.distribution == "rectangular":
            return self.value + self.spread * rng.uniform(-1.0, 1.0, trials)
        return self.value + self.spread * (rng.uniform(0.0, 1.0, trials)
                                           - rng.uniform(0.0, 1.0, trials))


@dataclass(frozen=True)
class GumResult:
    value: float                   # y = f(x)
    standard: float                # u_c(y)
    sensitivities: tuple           # c_i = ∂f/∂x_i
    contributions: tuple           # c_i·u(x_i), signed
    shares: tuple                  # each input's share of u_c²(y) without correlation terms

    def interval(self, coverage: float = 0.95) -> tuple[float, float]:
        """y ± k·u_c with k the normal quantile for ``coverage`` (GUM §G.1.3, a normal
        output assumed)."""
        k = NormalDist().inv_cdf(0.5 + coverage / 2.0)
        return self.value - k * self.standard, self.value + k * self.standard


def gum(f: Callable[[np.ndarray], float], inputs: Sequence[Input],
        correlation: np.ndarray | None = None, relative_step: float = 1e-6) -> GumResult:
    """The GUM uncertainty framework for y = f(x) at the inputs' estimates.

    ``f`` takes the vector of input values (in ``inputs``' order).  The sensitivity
    coefficients are central differences with a step of ``relative_step`` times the
    input's standard uncertainty (or its value when that is zero); ``correlation`` is the
    inputs' correlation matrix (default: independent)."""
    x = np.array([i.value for i in inputs], dtype=float)
    u = np.array([i.standard for i in inputs], dtype=float)
    y = float(f(x))
    c = np.zeros(len(inputs))
    for index, item in enumerate(inputs):
        step = relative_step * (u[index] if u[index] > 0 else max(abs(x[index]), 1.0))
        up, down = x.copy(), x.copy()
        up[index] += step
        down[index] -= step
        c[index] = (float(f(up)) - float(f(down))) / (2.0 * step)
    contributions = c * u
    r = np.eye(len(inputs)) if correlation is None else np.asarray(correlation, dtype=float)
    variance = float(contributions @ r @ contributions)
    squares = contributions ** 2
    total = float(squares.sum())
    shares = tuple(float(s / total) if total > 0 else 0.0 for s in squares)
    return GumResult(y, math.sqrt(max(variance, 0.0)), tuple(map(float, c)),
                     tuple(map(float, contributions)), shares)


@dataclass(frozen=True)
class MonteCarloResult:
    value: float                   # the mean of the output values (JCGM 101 §7.6)
    standard: float                # their standard deviation
    interval: tuple[float, float]  # probabilistically symmetric coverage interval (§7.7)
    coverage: float
    trials: int


def monte_carlo(f: Callable[[np.ndarray], np.ndarray], inputs: Sequence[Input],
                trials: int = 100_000, seed: int = 0,
                coverage: float = 0.95) -> MonteCarloResult:
    """Propagation of distributions (JCGM 101 §7) for independent inputs.

    ``f`` takes an array of shape (inputs, trials) and returns the trials' output values;
    the draws come from one generator seeded with ``seed``, input by input, so the same
    call gives the same numbers."""
    if trials < 1:
        raise ValueError(f"trials must be ≥ 1, found {trials}")
    rng = np.random.default_rng(seed)
    draws = np.vstack([item.draws(rng, trials) for item in inputs])
    return summarise(np.asarray(f(draws), dtype=float), coverage)


def summarise(values: np.ndarray, coverage: float = 0.95) -> MonteCarloResult:
    """The estimate, standard uncertainty and probabilistically symmetric coverage interval
    of the output values of a Monte Carlo propagation (JCGM 101 §7.6, §7.7)."""
    values = np.sort(np.asarray(values, dtype=float))
    trials = values.size
    # §7.7.1: the probabilistically symmetric interval [y_(r), y_(r+q)] of the sorted
    # values (1-based), q = pM (its integer part + 1/2 when pM is not an integer), r =
    # (M − q)/2 when M − q is even and (M − q + 1)/2 when it is odd
    q = int(coverage * trials + 0.5)
    r = max((trials - q + 1) // 2, 1)
    low, high = values[r - 1], values[min(r + q, trials) - 1]
    return MonteCarloResult(float(values.mean()), float(values.std(ddof=1)),
                            (float(low), float(high)), coverage, trials)


def tolerance(standard: float, digits: int = 2) -> float:
    """JCGM 101 §8.2: δ = 10^l / 2 when u(y) written with ``digits`` significant digits is
    c × 10^l, c an integer of ``digits`` digits."""
    if not standard > 0:
        return 0.0
    exponent = math.floor(math.log10(standard)) - (digits - 1)
    if round(standard / 10.0 ** exponent) >= 10 ** digits:      # 9.96 → 10 with 2 digits
        exponent += 1
    return 0.5 * 10.0 ** exponent


def validated(result: GumResult, check: MonteCarloResult, digits: int = 2
              ) -> tuple[bool, float, float, float]:
    """JCGM 101 §8.2: (whether both end points agree within δ, δ, d_low, d_high), the GUM
    interval taken at the Monte Carlo check's coverage."""
    low, high = result.interval(check.coverage)
    delta = tolerance(result.standard, digits)
    d_low, d_high = abs(low - check.interval[0]), abs(high - check.interval[1])
    return (d_low <= delta and d_high <= delta), delta, d_low, d_high


def conformance_probability(value: float, standard: float, lower: float | None = None,
                            upper: float | None = None) -> float:
    """p_c = Φ((T_U − y)/u) − Φ((T_L − y)/u) for a normal PDF of the measurand with
    expectation y and standard deviation u (JCGM 106:2012 §7.3); a missing limit is an
    open side.  With u = 0 the probability is 1 inside the limits and 0 outside."""
    phi = NormalDist().cdf
    if standard == 0:
        inside = (lower is None or value >= lower) and (upper is None or value <= upper)
        return 1.0 if inside else 0.0
    above = 1.0 if upper is None else phi((upper - value) / standard)
    below = 0.0 if lower is None else phi((lower - value) / standard)
    return above - below


# --------------------------------------------------------------------------- decision rules
#: The decision rules of ILAC-G8:09/2019 certkit applies (§4.2): simple acceptance (the
#: guard band w = 0, §4.2.1), guarded acceptance with w = r·U (§4.2.2; r = 1: w = U), and a
#: required conformance probability (JCGM 106:2012 §8.3: accept when p_c ≥ the required).
RULES = ("simple", "guarded", "probability")


@dataclass(frozen=True)
class Decision:
    """A statement of conformity: the binary outcome and, for a guarded rule, the
    non-binary one of ILAC-G8 §4.2.3 (pass / conditional pass / conditional fail / fail)."""

    outcome: str               # "PASS" | "FAIL"
    statement: str             # "pass", "conditional pass", "conditional fail", "fail"
    conformance: float | None  # p_c (None without an uncertainty)
    acceptance: tuple          # (lower, upper) acceptance limits (None: open side)


def decide(value: float, expanded: float | None, k: float, lower: float | None = None,
           upper: float | None = None, rule: str = "simple", r: float = 1.0,
           required: float = 0.95, conformance: float | None = None) -> Decision:
    """The statement of conformity of ``value`` (expanded uncertainty ``expanded`` at
    coverage factor ``k``, a normal PDF assumed for p_c) against the tolerance limits.

    Acceptance limits: the tolerance limits moved inward by the guard band w (0 for simple
    acceptance, r·U for guarded acceptance).  The binary outcome is PASS inside them.  The
    non-binary statement (ILAC-G8 §4.2.3) is "pass" when the value is inside the acceptance
    limits, "conditional pass" inside the tolerance limits but within w of them,
    "conditional fail" outside by less than w, and "fail" beyond.  Under a required
    conformance probability, PASS when p_c ≥ ``required``.  ``conformance`` replaces the
    normal p_c (a Monte Carlo one, the share of the draws that conform)."""
    if rule not in RULES:
        raise ValueError(f"decision rule {rule!r} is not one of {', '.join(RULES)}")
    known = expanded is not None
    standard = expanded / k if known else 0.0
    p = (conformance if conformance is not None
         else conformance_probability(value, standard, lower, upper) if known else None)
    w = r * expanded if (rule == "guarded" and known) else 0.0
    acceptance = (None if lower is None else lower + w, None if upper is None else upper - w)
    inside_tolerance = (lower is None or value >= lower) and (upper is None or value <= upper)
    inside_acceptance = ((acceptance[0] is None or value >= acceptance[0])
                         and (acceptance[1] is None or value <= acceptance[1]))
    if rule == "probability":
        if not known:
            raise ValueError("a required conformance probability needs an uncertainty")
        passed = p >= required
        return Decision("PASS" if passed else "FAIL", "pass" if passed else "fail", p,
                        acceptance)
    if inside_acceptance:
        statement = "pass"
    elif inside_tolerance:
        statement = "conditional pass"
    else:
        beyond = max((lower - value) if lower is not None else -math.inf,
                     (value - upper) if upper is not None else -math.inf)
        statement = "conditional fail" if beyond < w else "fail"
    return Decision("PASS" if inside_acceptance else "FAIL", statement, p, acceptance)
