"""Regulatory formulas pinned to values worked out by hand from the clause text."""

import math

import pytest

from certkit.compliance import clauses
from certkit.spec.requirement_sets import load
from certkit.units import ureg

LB_FT2 = ureg.Quantity(1.0, "lbf/ft^2").to("Pa").magnitude  # 47.880 Pa
INCH = 0.0254


def required(wing_loading_lb_ft2: float, set_id: str = "14CFR23-amdt62"):
    rules = load(set_id)
    units = rules.parameters["drop_height_formula_units"]
    return clauses.required_drop_height(
        wing_loading_lb_ft2 * LB_FT2, rules.number("drop_height_coefficient"),
        units["wing_loading"], units["height"], rules.length("drop_height_minimum"),
        rules.length("drop_height_maximum"))


def test_drop_height_of_the_seed_airplane_from_1430_lb_and_140_85_ft2():
    # W/S = 1430/140.85 = 10.15264 lb/ft^2; h = 3.6*sqrt(10.15264) = 11.47076 in = 291.357 mm
    height = required(1430 / 140.85)
    assert height.bound is None
    assert height.required == pytest.approx(11.470757 * INCH, rel=1e-6)
    assert height.required * 1000 == pytest.approx(291.3572, abs=1e-3)


def test_drop_height_is_clamped_to_9_2_inches():
    # 3.6*sqrt(5) = 8.05 in < 9.2 in
    height = required(5.0)
    assert height.formula == pytest.approx(3.6 * math.sqrt(5.0) * INCH, rel=1e-9)
    assert height.required == pytest.approx(9.2 * INCH, rel=1e-12)
    assert height.bound == "minimum"


def test_drop_height_need_not_exceed_18_7_inches():
    # 3.6*sqrt(30) = 19.72 in > 18.7 in
    height = required(30.0)
    assert height.required == pytest.approx(18.7 * INCH, rel=1e-12)
    assert height.bound == "maximum"


def test_effective_weight_of_23_725b_by_hand():
    # W = 1000 N, h = 0.3 m, d = 0.15 m, L = 0.667: W_e = 1000*(0.3 + 0.333*0.15)/0.45
    assert clauses.effective_weight(1000.0, 0.3, 0.15, 0.667) == pytest.approx(777.6666667, rel=1e-9)
    # L = 1 reduces to the reserve form W*h/(h+d) of 23.727(b)
    assert clauses.effective_weight(1000.0, 0.3, 0.15, 1.0) == pytest.approx(
        clauses.reserve_effective_weight(1000.0, 0.3, 0.15))
    assert clauses.reserve_effective_weight(1000.0, 0.3, 0.15) == pytest.approx(666.6666667, rel=1e-9)


def test_inertia_load_factor_of_23_725e_by_hand():
    # n = n_j*W_e/W + L = 3.0 * 777.6666667/1000 + 0.667 = 2.333 + 0.667 = 3.000
    assert clauses.inertia_load_factor(3.0, 777.6666667, 1000.0, 0.667) == pytest.approx(3.0, abs=1e-9)
    # without lift: n_j = 4.2, full weight dropped -> n = 4.2
    assert clauses.inertia_load_factor(4.2, 1000.0, 1000.0, 0.0) == 4.2


def test_drop_test_load_factor_adds_one_g_only_to_kinematic_acceleration():
    assert clauses.drop_test_load_factor(2 * 9.80665, "kinematic") == pytest.approx(3.0)
    assert clauses.drop_test_load_factor(2 * 9.80665, "specific_force") == pytest.approx(2.0)


def test_reserve_and_dynamic_factors_come_from_the_rule_text():
    rules = load("14CFR23-amdt62")
    assert rules.number("reserve_height_factor") == 1.44  # 23.727(a)
    assert rules.number("dynamic_height_factor") == 2.25  # 23.726(a)(1)
    assert rules.number("wing_lift_ratio_maximum") == 0.667  # 23.725(b)


def test_energy_method_load_factor_reproduces_the_seed_formula():
    # seed: n_j = (h + d/3)/(0.5*d_tire + 0.65*d_shock); 300 mm left: d_t 52.47, d_s 97.85 mm
    n = clauses.energy_method_load_factor(0.300, 0.05247, 0.09785, 2 / 3, 0.5, 0.65)
    by_hand = (300 + (52.47 + 97.85) / 3) / (0.5 * 52.47 + 0.65 * 97.85)
    assert by_hand == pytest.approx(3.89711, abs=1e-5)
    assert n == pytest.approx(by_hand, rel=1e-12)


def test_limit_descent_velocity_of_23_473d():
    # W/S = 10.15264 lb/ft^2: V = 4.4*10.15264^0.25 = 4.4*1.785027 = 7.85412 ft/s = 2.39394 m/s
    formula, bounded = clauses.limit_descent_velocity(1430 / 140.85 * LB_FT2)
    assert bounded == pytest.approx(2.39394, abs=1e-5)
    assert formula == bounded
    _, low = clauses.limit_descent_velocity(1.0 * LB_FT2)  # 4.4 ft/s -> 7 ft/s
    assert low == pytest.approx(7 * 0.3048)


def test_available_energy_subtracts_lift_work():
    # W(h+d) - L W d = 1000*(0.45) - 0.5*1000*0.15
    assert clauses.available_energy(1000.0, 0.3, 0.15, 0.5) == pytest.approx(375.0)
