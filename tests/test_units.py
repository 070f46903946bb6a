"""Quantities typed by users: dimensions enforced, SI inside, stated precision kept."""

import pytest

from certkit.units import QuantityError, parse_quantity


def test_quantities_are_converted_to_si():
    assert parse_quantity("140.85 ft^2", "area").si == pytest.approx(13.0853932, rel=1e-8)
    assert parse_quantity("831.92 kgf", "force").si == pytest.approx(831.92 * 9.80665)
    assert parse_quantity("650 kg", "weight").si == pytest.approx(650 * 9.80665)
    assert parse_quantity("0.8 MPa", "pressure").si == 8.0e5
    assert parse_quantity("10 %", "dimensionless").si == pytest.approx(0.1)


def test_a_bare_number_where_a_dimension_is_required_is_refused():
    with pytest.raises(QuantityError, match="bare number 300"):
        parse_quantity(300, "length")


def test_a_wrong_dimension_names_what_was_expected_and_found():
    with pytest.raises(QuantityError, match='expected a length, got "0.3 m/s"'):
        parse_quantity("0.3 m/s", "length")


def test_an_unknown_unit_is_refused():
    with pytest.raises(QuantityError, match="expected a length"):
        parse_quantity("3 bananas", "length")


def test_stated_resolution_is_half_the_last_digit():
    assert parse_quantity("4.8", "dimensionless").stated_resolution_si == pytest.approx(0.05)
    assert parse_quantity("11.69 in", "length").stated_resolution_si == pytest.approx(0.005 * 0.0254)
    assert parse_quantity("300 mm", "length").stated_resolution_si == pytest.approx(0.0005)
