"""Numbers as a person reads them (certkit.display) and the display units a spec chooses."""

from __future__ import annotations

import pytest

from certkit.display import number, parameter, pretty, typed, with_unit
from certkit.spec.schema import DisplayUnits

LBF = 4.4482216152605      # N, exact (0.45359237 kg · 9.80665 m/s²)
US = DisplayUnits.model_validate({"length": "in", "force": "lbf"})
SI = DisplayUnits()


@pytest.mark.parametrize("value, text", [
    (12471.77, "12470"), (831.92, "831.9"), (2.53123, "2.531"), (645.0, "645.0"),
    (4.0, "4.000"), (0.001234, "0.001234"), (0.0, "0"),
    (1.5e-5, "1.500×10⁻⁵"), (1234567.0, "1.235×10⁶"), (-3.2e-7, "-3.200×10⁻⁷"),
])
def test_four_significant_figures_with_powers_of_ten_written_out(value, text):
    assert number(value) == text


@pytest.mark.parametrize("unit, text", [
    ("ft*lbf", "ft·lbf"), ("lbf/ft^2", "lbf/ft²"), ("m/s**2", "m/s²"), ("kg*m^-3", "kg·m⁻³"),
    ("in", "in"),
])
def test_units_are_printed_as_a_person_writes_them(unit, text):
    assert pretty(unit) == text


def test_values_are_converted_to_the_display_unit():
    # 2869 N = 645.0 lbf; 1 J = 0.7376 ft·lbf
    assert with_unit(645 * LBF, "force", US) == "645.0 lbf"
    assert with_unit(1.0, "energy", US) == "0.7376 ft·lbf"
    assert with_unit(0.3, "length", SI) == "300.0 mm"
    assert with_unit(None, "length", SI) == "—"


def test_a_typed_value_keeps_its_digits_when_typed_in_the_display_unit():
    assert typed("831.92 kgf", 831.92 * 9.80665, "force",
                 DisplayUnits.model_validate({"force": "kgf"})) == ("831.92", "kgf")
    # typed in another unit: converted like any computed value (300 mm = 11.81 in)
    assert typed("300 mm", 0.3, "length", US) == ("11.81", "in")
    assert typed("0.667", 0.667, "ratio", US) == ("0.667", "")


def test_model_parameters_follow_the_display_unit_of_their_kind():
    assert parameter(800000.0, "Pa", US) == ("116.0", "psi")   # 0.8 MPa = 116.03 psi
    assert parameter(80.0, "N", US) == ("17.98", "lbf")
    assert parameter(0.6, "1", US) == ("0.6000", "")
    # a compound unit in the display units of its parts: 6.5e-4 m³ / (0.0254 m)³ = 39.67 in³,
    # 1.832e4 N·s²/m² × (0.0254 m)²/4.448222 N = 2.657 lbf·s²/in², 5 s/m × 0.0254 = 0.127 s/in
    assert parameter(6.5e-4, "m^3", US) == ("39.67", "in³")
    assert parameter(1.832e4, "N*s^2/m^2", US) == ("2.657", "lbf·s²/in²")
    assert parameter(5.0, "s/m", US) == ("0.1270", "s/in")


@pytest.mark.parametrize("given, expected", [
    ({"length": "in"}, {"energy": "ft*lbf", "area": "ft^2", "pressure": "psi", "mass": "lb"}),
    ({"force": "lbf"}, {"length": "in", "energy": "ft*lbf", "velocity": "ft/s"}),
    ({"length": "mm", "force": "kgf", "wing_loading": "lbf/ft^2"},
     {"energy": "J", "area": "m^2", "force": "kgf", "wing_loading": "lbf/ft^2"}),
    ({"system": "US", "length": "mm"}, {"length": "mm", "force": "lbf"}),
    ({}, {"length": "mm", "force": "N", "energy": "J"}),
])
def test_units_not_given_follow_the_system_of_those_given(given, expected):
    units = DisplayUnits.model_validate(given)
    assert {key: getattr(units, key) for key in expected} == expected


def test_unit_text_is_normalised():
    units = DisplayUnits.model_validate({"length": " in ", "energy": "ft * lbf"})
    assert (units.length, units.energy) == ("in", "ft*lbf")
