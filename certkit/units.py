"""Units at the edges: parsing quantities typed by users and formatting them back.

Everything inside certkit is SI (m, kg, s, N, Pa, J).  A user types quantities
with their unit (``"650 kg"``, ``"140.85 ft^2"``); :func:`parse_quantity` checks
the dimension and returns a :class:`SpecQuantity` carrying the SI magnitude and
the text as typed, so the report can quote the user's own value.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import pint

from certkit.errors import shown


def _registry() -> pint.UnitRegistry:
    try:  # pint's definition cache turns a 0.3 s registry build into 0.05 s
        return pint.UnitRegistry(cache_folder=":auto:")
    except OSError:
        return pint.UnitRegistry()


#: The one unit registry of the process (quantities from two registries cannot be mixed).
ureg = _registry()

#: Standard acceleration of gravity [m/s^2] (also 1 kgf = 9.80665 N), ISO 80000-3.
STANDARD_GRAVITY = 9.80665

#: Named physical kinds accepted in a campaign spec, with the pint dimensionality
#: they must have and the SI unit they are stored in.
KINDS: dict[str, tuple[str, str]] = {
    "length": ("[length]", "m"),
    "area": ("[length]**2", "m**2"),
    "volume": ("[length]**3", "m**3"),
    "mass": ("[mass]", "kg"),
    "force": ("[force]", "N"),
    "pressure": ("[pressure]", "Pa"),
    "energy": ("[energy]", "J"),
    "time": ("[time]", "s"),
    "frequency": ("1/[time]", "Hz"),
    "velocity": ("[length]/[time]", "m/s"),
    "acceleration": ("[length]/[time]**2", "m/s**2"),
    "angle": ("[]", "rad"),
    "wing_loading": ("[pressure]", "Pa"),
    "density": ("[mass]/[length]**3", "kg/m**3"),
    "slowness": ("[time]/[length]", "s/m"),
    "stiffness": ("[force]/[length]", "N/m"),
    "damping": ("[force]*[time]/[length]", "N*s/m"),
}

_ARTICLE = {"area": "an area", "acceleration": "an acceleration", "angle": "an angle",
            "energy": "an energy"}


def kind_phrase(kind: str) -> str:
    """'a length', 'an area', ... for error messages."""
    if kind == "weight":
        return "a weight (a force such as '2868 N' or '292.5 kgf', or a mass such as '650 kg')"
    return _ARTICLE.get(kind, f"a {kind.replace('_', ' ')}")


@dataclass(frozen=True)
class SpecQuantity:
    """A quantity as typed in a spec: SI magnitude plus the user's own text.

    Attributes
    ----------
    si : float
        Magnitude in the SI unit of its kind.
    unit : str
        The SI unit ``si`` is expressed in (``"m"``, ``"N"``, ...).
    text : str
        The value exactly as the user typed it (``"300 mm"``).
    """

    si: float
    unit: str
    text: str

    def __str__(self) -> str:  # pragma: no cover - convenience
        return self.text

    @property
    def stated_resolution_si(self) -> float:
        """Half a unit in the last digit the user typed, in SI.

        ``"4.8"`` states 4.8 +- 0.05; ``"831.92 kgf"`` states +- 0.005 kgf.  Used to
        decide whether a recomputed value agrees with a reported one "to the
        precision stated".
        """
        magnitude_text, unit_text = _split_magnitude(self.text)
        decimals = len(magnitude_text.split(".")[1]) if "." in magnitude_text else 0
        exponent_match = re.search(r"[eE]([+-]?\d+)", magnitude_text)
        if exponent_match:
            mantissa = magnitude_text[: exponent_match.start()]
            decimals = (len(mantissa.split(".")[1]) if "." in mantissa else 0) - int(
                exponent_match.group(1))
        half_step = 0.5 * 10.0 ** (-decimals)
        if not unit_text:
            return half_step
        return float(ureg.Quantity(half_step, unit_text).to(self.unit).magnitude)


#: The longest text read as a quantity or a unit: far beyond any value a person types, and
#: a bound on the work (and the echo) a pasted or generated value can cause.
MAX_TEXT = 100
#: Magnitudes certkit computes with, in SI: zero, or 1e-12 to 1e12 in absolute value.  The
#: smallest gap in a drop test (an orifice area, 1e-6 m^2 and below) and the largest
#: modulus (steel, 2e11 Pa) lie well inside; a value beyond is a typing slip, and products
#: of such values underflow or overflow a float (5e-324 kgf times a stroke is 0).
SI_RANGE = (1e-12, 1e12)

# A number is digits with one optional decimal point and exponent; written so that one
# character can be matched one way only (no backtracking on long digit strings).
_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
# A unit is names joined by * / or ·, each with an optional small integer power, not zero
# (m/s^2, lbf/ft**2, kg·m^-3, %).  Nothing else reaches pint, so no arithmetic typed by a
# user (1/0 mm, 2**10000 mm, 11 ft + 8 in) is ever evaluated.
_NAME = r"(?:%|[A-Za-z_°µΩ][A-Za-z_°µΩ0-9]*)"
_UNIT_NAME = rf"{_NAME}(?:\s*(?:\^|\*\*)\s*[+-]?(?:0?[1-9]|[1-9]\d))?"
_UNIT = rf"{_UNIT_NAME}(?:\s*[*/·]\s*{_UNIT_NAME})*"
_QUANTITY = re.compile(rf"^\s*({_NUMBER})\s*({_UNIT})?\s*$")
_ANGULAR = re.compile(r"rpm|rev|rad|deg|turn|cycle", re.IGNORECASE)


def _split_magnitude(text: str) -> tuple[str, str]:
    match = _QUANTITY.match(text) if len(text) <= MAX_TEXT else None
    if not match:
        return text, ""
    return match.group(1), (match.group(2) or "").strip()


class QuantityError(ValueError):
    """A value that is not a quantity of the expected kind."""


def _scale_of(unit: pint.Unit) -> float:
    """SI (root-unit) value of one ``unit``; QuantityError for a unit that does not scale
    linearly (logarithmic such as dB, or with an offset such as degC)."""
    zero, one, two = (float(ureg.Quantity(value, unit).to_root_units().magnitude)
                      for value in (0.0, 1.0, 2.0))
    if zero != 0 or not math.isclose(two, 2 * one):
        raise QuantityError("logarithmic or offset")
    return one


def _unit(text: str) -> pint.Unit:
    """``text`` (matched by ``_UNIT``) as a pint unit that scales linearly to SI, or
    QuantityError giving the reason (callers say what was expected).

    This is the one place user text reaches pint.  For text it cannot use, pint raises its
    own errors but also KeyError (``mm^0``), AttributeError and AssertionError (products
    with ``dB``) and OverflowError (``km^99*km^99``): all mean "not a unit certkit can use",
    so all are caught here.
    """
    for name in dict.fromkeys(re.findall(_NAME, text)):
        try:
            _scale_of(ureg.Unit(name))
        except QuantityError:
            raise QuantityError(f'"{name}" is a logarithmic or offset unit (such as dB or '
                                f'degC), which certkit cannot scale') from None
        except Exception:  # noqa: BLE001 - pint's parser raises many types, see above
            raise QuantityError(f"unknown unit {shown(name)}") from None
    try:
        unit = ureg.Unit(text)
        scale = _scale_of(unit)
    except OverflowError:
        raise QuantityError(f"the unit {shown(text)} is too large or too small to "
                            f"compute with") from None
    except Exception:  # noqa: BLE001 - as above
        raise QuantityError(f"unknown unit {shown(text)}") from None
    if not (math.isfinite(scale) and scale != 0
            and SI_RANGE[0] ** 2 <= abs(scale) <= SI_RANGE[1] ** 2):
        raise QuantityError(f"the unit {shown(text)} is too large or too small to compute "
                            f"with")
    return unit


def _to_weight_newton(quantity: pint.Quantity) -> float:
    if quantity.check("[force]"):
        return float(quantity.to("N").magnitude)
    if quantity.check("[mass]"):
        return float(quantity.to("kg").magnitude) * STANDARD_GRAVITY
    raise QuantityError


def _read(text: str, expected: str, kind: str) -> pint.Quantity:
    """Number and unit from text of the strict form '<decimal number> <unit>'."""
    match = _QUANTITY.match(text) if len(text) <= MAX_TEXT else None
    if not match:
        hint = (f" (at most {MAX_TEXT} characters)" if len(text) > MAX_TEXT else
                " (write a decimal point, not a comma)" if "," in text else
                f' (write one decimal number and a unit, e.g. "300 {example_unit(kind)}")'
                if kind != "dimensionless" else " (write one decimal number, e.g. 4.4 or \"10 %\")")
        raise QuantityError(f"expected {expected}, got {shown(text)}{hint}")
    magnitude = float(match.group(1))
    if not math.isfinite(magnitude):
        raise QuantityError(f"expected a finite number, got {shown(text)}")
    unit_text = (match.group(2) or "").strip()
    if not unit_text:
        return ureg.Quantity(magnitude, "dimensionless")
    try:
        unit = _unit(unit_text)
    except QuantityError as problem:
        hint = ('; write a ratio as a number or a percentage, e.g. 0.5 or "50 %"'
                if kind == "dimensionless" else "")
        raise QuantityError(f"expected {expected}, got {shown(text)} ({problem}){hint}") \
            from None
    return ureg.Quantity(magnitude, unit)


def _in_range(si: float, unit: str, text: str) -> None:
    """QuantityError unless ``si`` is finite and zero or within :data:`SI_RANGE`."""
    if not math.isfinite(si):
        raise QuantityError(f"expected a finite value, got {shown(text)}")
    if si != 0 and not SI_RANGE[0] <= abs(si) <= SI_RANGE[1]:
        low, high = (f"{bound:.0e}".replace("+", "") for bound in SI_RANGE)
        unit = f" {unit}" if unit else ""
        raise QuantityError(f"{shown(text)} is {si:.3g}{unit}, outside the magnitudes "
                            f"certkit computes with (zero, or {low} to {high}{unit})")


def parse_quantity(value: object, kind: str) -> SpecQuantity:
    """Parse ``value`` (text such as ``"300 mm"``) as a quantity of ``kind``.

    ``kind`` is a key of :data:`KINDS`, ``"weight"`` (force or mass, stored in N
    using standard gravity) or ``"dimensionless"`` (a bare number or a percentage).
    A bare number where a dimension is required is refused: a unit must be typed.
    The text must be one decimal number and a unit: expressions are refused, and so are
    logarithmic units (dB) and magnitudes outside :data:`SI_RANGE`.

    Raises
    ------
    QuantityError
        With a message of the form ``expected a length, got "0.3 m/s"``.
    """
    if kind == "dimensionless":
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise QuantityError(f"expected a number, got {shown(value)}")
        if isinstance(value, (int, float)):
            try:
                number = float(value)
            except OverflowError:
                raise QuantityError(f"expected a number, got {shown(value)}") from None
            _in_range(number, "", shown(value))
            return SpecQuantity(number, "1", str(value))
        quantity = _read(value.strip(), "a number", kind)
        if not quantity.dimensionless or _ANGULAR.search(value):
            raise QuantityError(f"expected a bare number (a ratio or a load factor), got "
                                f"{shown(value)}; write it without a unit, e.g. 4.4 or \"10 %\"")
        si = float(quantity.to("dimensionless").magnitude)
        _in_range(si, "", value.strip())
        return SpecQuantity(si, "1", value.strip())

    expected = kind_phrase(kind)
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise QuantityError(f"expected {expected} with its unit, got {shown(value)}")
    if not isinstance(value, str):
        example = (f' (write the unit, e.g. "{value} {example_unit(kind)}")'
                   if len(shown(value)) < 30 else "")
        raise QuantityError(f"expected {expected} with its unit, got the bare number "
                            f"{shown(value)}{example}")
    text = value.strip()
    quantity = _read(text, expected, kind)
    if kind != "angle" and (quantity.unitless or quantity.dimensionless):
        if str(quantity.units) == "dimensionless":
            raise QuantityError(
                f'expected {expected} with its unit, got {shown(text)} without a unit '
                f'(e.g. "{text} {example_unit(kind)}")')
        raise QuantityError(f"expected {expected}, got {shown(text)} (a pure number or ratio)")
    if kind == "frequency" and _ANGULAR.search(text):
        raise QuantityError(f"expected a frequency in Hz, got {shown(text)} (an angular rate)")
    try:
        if kind == "weight":
            si, unit = _to_weight_newton(quantity), "N"
        elif kind == "angle":
            if str(quantity.units) == "dimensionless":
                raise QuantityError(
                    f'expected an angle with its unit, got {shown(text)} (e.g. "{text} deg")')
            si, unit = float(quantity.to("rad").magnitude), "rad"
        else:
            dimension, unit = KINDS[kind]
            if not quantity.check(dimension):
                raise QuantityError
            si = float(quantity.to(unit).magnitude)
    except (QuantityError, pint.errors.DimensionalityError):
        raise QuantityError(f"expected {expected}, got {shown(text)}") from None
    _in_range(si, unit, text)
    return SpecQuantity(si, unit, text)


def example_unit(kind: str) -> str:
    return {"length": "mm", "area": "m^2", "volume": "L", "mass": "kg", "force": "N",
            "pressure": "MPa", "energy": "J", "time": "s", "frequency": "Hz",
            "velocity": "m/s", "acceleration": "m/s^2", "angle": "deg", "weight": "kg",
            "wing_loading": "lbf/ft^2", "density": "kg/m^3", "slowness": "s/m",
            "stiffness": "N/mm", "damping": "N*s/m"}.get(kind, "")


def parse_unit(text: str, kind: str) -> str:
    """Check that ``text`` names a unit of ``kind`` and return it unchanged."""
    if not isinstance(text, str) or len(text) > MAX_TEXT \
            or not re.fullmatch(rf"\s*{_UNIT}\s*", text):
        raise QuantityError(f"expected a unit of {kind} (names joined by * or /, such as "
                            f"mm or lbf/ft^2), got {shown(text)}")
    try:
        unit = _unit(text.strip())
    except QuantityError as problem:
        raise QuantityError(f"expected a unit of {kind}, got {shown(text)} ({problem})") \
            from None
    if kind == "weight":
        ok = (1 * unit).check("[force]") or (1 * unit).check("[mass]")
    elif kind == "dimensionless":
        ok = (1 * unit).dimensionless
    else:
        ok = (1 * unit).check(KINDS[kind][0])
    if not ok:
        hint = " ('g' is the gram; write g0 for standard gravity)" if text.strip() == "g" else ""
        raise QuantityError(f"expected a unit of {kind}, got {shown(text)}{hint}")
    return text


def convert(value_si: float, si_unit: str, unit: str) -> float:
    """Convert an SI magnitude to ``unit`` (for display at the edges)."""
    if si_unit == unit:
        return value_si
    if si_unit == "N" and (1 * ureg.Unit(unit)).check("[mass]"):
        return float(ureg.Quantity(value_si / STANDARD_GRAVITY, "kg").to(unit).magnitude)
    return float(ureg.Quantity(value_si, si_unit).to(unit).magnitude)


def scale_to_si(unit: str, kind: str) -> float:
    """Multiplier taking values in ``unit`` to SI (all data-channel units are linear)."""
    if kind == "force" and (1 * ureg.Unit(unit)).check("[mass]"):
        return float(ureg.Quantity(1.0, unit).to("kg").magnitude) * STANDARD_GRAVITY
    return float(ureg.Quantity(1.0, unit).to(KINDS[kind][1]).magnitude)
