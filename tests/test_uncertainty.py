"""Uncertainty propagation and conformance (certkit.compliance.uncertainty), against
figures worked out apart from the code: by hand, from closed-form distributions, and from
the published worked examples' set-up (JCGM 101:2008 §9.2, the additive model)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from certkit.compliance.uncertainty import (Input, conformance_probability, gum, monte_carlo,
                                            tolerance, validated)

SQRT3 = math.sqrt(3.0)


def _sum(x):
    return np.sum(x, axis=0)


def test_standard_uncertainties_of_the_distributions_by_hand():
    assert Input("a", 0.0, "rectangular", 3.0).standard == pytest.approx(3.0 / SQRT3)
    assert Input("a", 0.0, "triangular", 6.0).standard == pytest.approx(6.0 / math.sqrt(6))
    # a certificate's U = 0.4 % at k = 2: u = 0.2 %
    assert Input.expanded("gain", 1.0, 0.004, 2.0).standard == pytest.approx(0.002)
    for bad in (dict(distribution="lognormal", spread=1.0), dict(distribution="normal",
                                                                 spread=-1.0)):
        with pytest.raises(ValueError):
            Input("x", 0.0, **bad)
    with pytest.raises(ValueError, match="coverage factor"):
        Input.expanded("x", 0.0, 1.0, 0.0)


def test_additive_model_of_four_normal_inputs():
    # JCGM 101 §9.2.2 set-up: Y = X1 + X2 + X3 + X4, each N(0, 1).  By hand: u(y) = √4 = 2
    # and the 95 % interval ±1.959964·2 = ±3.92 (the sum of normals is normal)
    inputs = [Input(f"X{i}", 0.0, "normal", 1.0) for i in range(1, 5)]
    result = gum(lambda x: float(np.sum(x)), inputs)
    assert result.standard == pytest.approx(2.0, rel=1e-9)
    assert result.interval(0.95)[1] == pytest.approx(3.919928, abs=1e-6)
    assert result.shares == pytest.approx((0.25,) * 4)
    check = monte_carlo(_sum, inputs, trials=1_000_000, seed=1)
    # 10⁶ trials: the standard deviation within a few of its standard error 2/√(2·10⁶)
    assert check.standard == pytest.approx(2.0, abs=0.005)
    assert check.interval[1] == pytest.approx(3.92, abs=0.02)
    ok, delta, _, _ = validated(result, check, digits=2)
    assert ok and delta == 0.05             # u = 2.0 to 2 digits: δ = ½·10⁻¹


def test_additive_model_of_four_rectangular_inputs_against_the_irwin_hall_quantile():
    # JCGM 101 §9.2.3 set-up: each X_i rectangular with u = 1 (half-width √3).  The sum of
    # four U(0, 1) has the Irwin–Hall CDF 1 − (4 − s)⁴/24 on [3, 4]: its 97.5 % quantile
    # is 4 − 0.6^(1/4), so Y's is 2√3·(4 − 0.6^(1/4) − 2) = 3.8795 (the GUM's ±3.92 is wider)
    exact = 2 * SQRT3 * (2.0 - 0.6 ** 0.25)
    assert exact == pytest.approx(3.8795, abs=1e-4)
    inputs = [Input(f"X{i}", 0.0, "rectangular", SQRT3) for i in range(1, 5)]
    check = monte_carlo(_sum, inputs, trials=1_000_000, seed=2)
    assert check.standard == pytest.approx(2.0, abs=0.005)
    # a 2.5 % quantile from 10⁶ draws has a standard error of √(0.025·0.975/10⁶)/f(q) =
    # 0.0048 (f(q) = (0.6^(1/4))³/6/(2√3) = 0.0328, Y's density there): within 3 of them
    assert check.interval[0] == pytest.approx(-exact, abs=0.015)
    assert check.interval[1] == pytest.approx(exact, abs=0.015)
    # against the exact distribution (a Monte Carlo result of infinitely many trials), the
    # GUM interval ±3.92 is validated to 2 digits (d = 0.040 ≤ δ = 0.05), not to 3 (δ = 0.005)
    from certkit.compliance.uncertainty import MonteCarloResult
    exact_check = MonteCarloResult(0.0, 2.0, (-exact, exact), 0.95, 10 ** 12)
    result = gum(lambda x: float(np.sum(x)), inputs)
    ok, delta, d_low, d_high = validated(result, exact_check, digits=2)
    assert ok and delta == 0.05 and d_low == pytest.approx(0.0405, abs=1e-4) == d_high
    assert not validated(result, exact_check, digits=3)[0]


def test_a_gain_times_a_force_has_the_root_sum_of_relative_uncertainties():
    # F = g·F_raw: u_rel(F)² = u_rel(g)² + u_rel(F_raw)² (GUM §5.1.6 for a product), by hand
    # 0.2 % and 0.15 % give 0.25 %; with the force's alone zero, F's relative U equals the
    # gain's
    inputs = [Input("gain", 1.0, "normal", 0.002), Input("F", 12000.0, "normal", 18.0)]
    result = gum(lambda x: x[0] * x[1], inputs)
    assert result.standard / result.value == pytest.approx(0.0025, rel=1e-6)
    assert result.sensitivities == pytest.approx((12000.0, 1.0), rel=1e-6)
    only_gain = gum(lambda x: x[0] * x[1], [inputs[0], Input("F", 12000.0, "normal", 0.0)])
    assert only_gain.standard / only_gain.value == pytest.approx(0.002, rel=1e-6)


def test_one_input_feeding_two_terms_and_correlated_inputs():
    # y = x1 + x2 with correlation 1 between them: u = u1 + u2 (GUM §5.2.2 note 1)
    inputs = [Input("a", 1.0, "normal", 0.3), Input("b", 2.0, "normal", 0.4)]
    full = gum(lambda x: x[0] + x[1], inputs, correlation=np.array([[1.0, 1.0], [1.0, 1.0]]))
    assert full.standard == pytest.approx(0.7)
    none = gum(lambda x: x[0] + x[1], inputs)
    assert none.standard == pytest.approx(0.5)


def test_the_conformance_probability_at_a_guarded_acceptance_limit():
    # JCGM 106:2012 §8: with the guard band w = U and U = 2u, a value on the acceptance
    # limit lies 2u inside the tolerance: p_c = Φ(2) = 0.97725, so the specific risk of false
    # acceptance of an accepted item is at most 2.3 %
    assert conformance_probability(102.0, 1.0, lower=100.0) == pytest.approx(0.977250,
                                                                             abs=1e-6)


def test_conformance_probability_by_hand():
    # y = 9.8, u = 0.1 under an upper limit 10: Φ(2) = 0.97725 (JCGM 106 §7.3, one limit)
    assert conformance_probability(9.8, 0.1, upper=10.0) == pytest.approx(0.977250, abs=1e-6)
    # a lower limit 9.7 as well: Φ(2) − Φ(−1) = 0.97725 − 0.15866
    assert conformance_probability(9.8, 0.1, 9.7, 10.0) == pytest.approx(0.818595, abs=1e-6)
    # on the limit: one half; zero uncertainty: today's verdict exactly
    assert conformance_probability(10.0, 0.3, upper=10.0) == pytest.approx(0.5)
    assert conformance_probability(10.0, 0.0, upper=10.0) == 1.0
    assert conformance_probability(10.0001, 0.0, upper=10.0) == 0.0


def test_the_numerical_tolerance_of_jcgm_101_section_8():
    # u = 0.0754 to 2 digits is 75 × 10⁻³ (0.075): δ = 0.5 × 10⁻³ (JCGM 101 §8.2)
    assert tolerance(0.0754, 2) == pytest.approx(0.0005)
    assert tolerance(2.0, 2) == pytest.approx(0.05)
    assert tolerance(9.96, 2) == pytest.approx(0.5)      # 9.96 → 10 (two digits: 1.0 × 10¹)


def test_monte_carlo_gives_the_same_numbers_for_the_same_seed():
    inputs = [Input("a", 1.0, "triangular", 0.2), Input("b", 2.0, "normal", 0.1)]
    first = monte_carlo(lambda x: x[0] * x[1], inputs, trials=10_000, seed=7)
    assert first == monte_carlo(lambda x: x[0] * x[1], inputs, trials=10_000, seed=7)
    assert first.interval[0] < first.value < first.interval[1]


# ------------------------------------------------------------------ JCGM 101 §9.3
def test_the_mass_calibration_of_jcgm_101_by_the_gum():
    # JCGM 101:2008 §9.3: δm = (m_W,c + δm_R,c)·(1 + (a − a0)·(1/ρ_W − 1/ρ_R)) − m_nom, with
    # m_W,c ~ N(100 000.000 mg, 0.050 mg), δm_R,c ~ N(1.234 mg, 0.020 mg), a rectangular
    # 1.20 ± 0.10 kg/m³, ρ_W rectangular 8000 ± 1000 kg/m³, ρ_R rectangular 8000 ± 50 kg/m³,
    # a0 = 1.20 kg/m³.  The GUM's first-order figures of its Table 9: δm = 1.2340 mg,
    # u = 0.0539 mg, 95 % interval [1.1285, 1.3395] mg (a, ρ_W and ρ_R enter through the
    # product (a − a0)·(1/ρ_W − 1/ρ_R), zero at the estimates: nothing to first order)
    a0, nominal = 1.20, 100_000.0
    inputs = [Input("m_W,c", 100_000.000, "normal", 0.050),
              Input("δm_R,c", 1.234, "normal", 0.020),
              Input("a", 1.20, "rectangular", 0.10),
              Input("ρ_W", 8e3, "rectangular", 1e3),
              Input("ρ_R", 8.00e3, "rectangular", 0.05e3)]

    def model(x):
        m, dm, a, rho_w, rho_r = x
        return (m + dm) * (1 + (a - a0) * (1 / rho_w - 1 / rho_r)) - nominal

    result = gum(model, inputs)
    assert round(result.value, 4) == 1.2340
    assert round(result.standard, 4) == 0.0539
    low, high = result.interval(0.95)
    assert (round(low, 4), round(high, 4)) == (1.1285, 1.3395)
    # the second-order product (a − a0)·(1/ρ_W − 1/ρ_R) makes the distribution wider than
    # the GUM's: Monte Carlo gives u ≈ 0.075 mg (two digits), so §8.2 does not validate it
    check = monte_carlo(model, inputs, trials=200_000, seed=4)
    assert round(check.standard, 3) == 0.075
    assert not validated(result, check, digits=2)[0]


# ------------------------------------------------------------------ decision rules
def test_decision_rules_of_ilac_g8_by_hand():
    from certkit.compliance.uncertainty import decide

    # a lower limit 100, a value 101 with U = 2 (k = 2, u = 1): p_c = Φ(1) = 0.8413
    simple = decide(101.0, 2.0, 2.0, lower=100.0)
    assert (simple.outcome, simple.statement) == ("PASS", "pass")
    assert simple.conformance == pytest.approx(0.841345, abs=1e-6)
    # guarded with w = U: acceptance limit 102, so 101 is a conditional pass, binary FAIL
    guarded = decide(101.0, 2.0, 2.0, lower=100.0, rule="guarded")
    assert guarded.acceptance == (102.0, None)
    assert (guarded.outcome, guarded.statement) == ("FAIL", "conditional pass")
    # 99 is outside the tolerance by 1 < w = 2: a conditional fail; 97 by 3: a fail
    assert decide(99.0, 2.0, 2.0, lower=100.0, rule="guarded").statement == "conditional fail"
    assert decide(97.0, 2.0, 2.0, lower=100.0, rule="guarded").statement == "fail"
    # w = 0.5·U: acceptance at 101, so 101 passes
    assert decide(101.0, 2.0, 2.0, lower=100.0, rule="guarded", r=0.5).outcome == "PASS"
    # a required conformance probability of 95 %: 0.84 fails, 104 (Φ(4)) passes
    assert decide(101.0, 2.0, 2.0, lower=100.0, rule="probability").outcome == "FAIL"
    assert decide(104.0, 2.0, 2.0, lower=100.0, rule="probability").outcome == "PASS"
    # no uncertainty stated: simple acceptance is today's verdict, with no p_c
    plain = decide(100.0, None, 2.0, lower=100.0)
    assert (plain.outcome, plain.conformance) == ("PASS", None)
    with pytest.raises(ValueError, match="needs an uncertainty"):
        decide(100.0, None, 2.0, lower=100.0, rule="probability")
    with pytest.raises(ValueError, match="not one of"):
        decide(100.0, 1.0, 2.0, lower=100.0, rule="shared risk")


def test_zero_uncertainty_gives_todays_outcomes_exactly():
    from certkit.compliance.uncertainty import decide

    for value, expected in ((99.999, "FAIL"), (100.0, "PASS"), (250.0, "PASS"),
                            (300.0, "PASS"), (300.001, "FAIL")):
        for rule in ("simple", "guarded"):
            assert decide(value, 0.0, 2.0, 100.0, 300.0, rule).outcome == expected
