"""Numbers as a person reads them: SI values in the campaign's display units, 4 figures.

Everything a person reads (the report, the terminal, audit Markdown and JUnit messages,
data-quality findings) is formatted here, so one rule holds everywhere; results.json and
the CSV tables keep full-precision SI and never pass through this module.

The rule
--------
* A value is shown to :data:`SIGNIFICANT` significant figures in the display unit of its
  kind (``report.units`` of the spec; see :class:`certkit.spec.schema.DisplayUnits`).
* A margin (value − limit, or limit − value) is shown to the same decimal place as the
  limit it is measured from, and as a percentage of that limit.  A tie (within
  :data:`~certkit.results.EQUALITY_TOLERANCE`) reads 0, never a float artefact such as
  1e-13; any other margin finer than the limit's last shown digit keeps its sign, to two
  significant figures.
* A value typed by the user is quoted as typed (its ``text``), not through this module.
"""

from __future__ import annotations

import math
import re

from certkit.results import EQUALITY_TOLERANCE
from certkit.units import convert

#: SI unit in which each physical kind is held inside certkit.
SI_UNITS = {"length": "m", "force": "N", "mass": "kg", "energy": "J", "velocity": "m/s",
            "pressure": "Pa", "area": "m^2", "time": "s", "wing_loading": "Pa"}
#: The kind of a quantity held in each SI unit (the inverse of SI_UNITS, where unambiguous).
KIND_OF_SI_UNIT = {"m": "length", "N": "force", "kg": "mass", "J": "energy", "m/s": "velocity",
                   "Pa": "pressure", "m^2": "area", "s": "time"}
#: Significant figures of every computed number a person reads.
SIGNIFICANT = 4
DISPLAY_RULE = (f"Computed values are shown to {SIGNIFICANT} significant figures in the units "
                f"chosen in the campaign's report.units; a margin to the decimal place of its "
                f"limit, and as a percentage of the limit; values typed in the spec are quoted as "
                f"typed. results.json and tables/*.csv hold full precision in SI.")


_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")
_PLAIN = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def number(value: float, digits: int = SIGNIFICANT) -> str:
    """``value`` to ``digits`` significant figures, powers of ten written out (1.2×10⁻⁵)."""
    if value == 0:
        return "0"
    if not math.isfinite(value):
        return str(value)
    rounded = float(f"{value:.{digits}g}")
    if 1e-3 <= abs(rounded) < 1e6:   # plain decimals: 12470, 0.001234
        decimals = max(0, digits - 1 - math.floor(math.log10(abs(rounded))))
        return f"{rounded:.{decimals}f}"   # the zeros are significant: 645.0, 4.000
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    return f"{mantissa}×10{str(int(exponent)).translate(_SUPERSCRIPT)}"


def pretty(unit: str) -> str:
    """A unit as printed: ``ft*lbf`` -> ``ft·lbf``, ``lbf/ft^2`` -> ``lbf/ft²``."""
    text = unit.replace("**", "^").replace("*", "·")
    return re.sub(r"\^(-?\d+)", lambda m: m.group(1).translate(_SUPERSCRIPT), text)


def unit_of(kind: str, units) -> str | None:
    """The display unit of ``kind`` (None for ratios and kinds without one)."""
    return getattr(units, kind, None) if kind in SI_UNITS else None


def to_display(value_si: float, kind: str, units) -> float:
    """An SI magnitude of ``kind`` in its display unit (unchanged for a ratio)."""
    unit = unit_of(kind, units)
    return value_si if unit is None else convert(value_si, SI_UNITS[kind], unit)


def display(value: float | None, kind: str, units, digits: int = SIGNIFICANT
            ) -> tuple[str, str]:
    """(number text, unit text) of an SI value in the campaign's display unit."""
    unit = pretty(unit_of(kind, units) or "")
    if value is None:
        return "—", unit
    return number(to_display(value, kind, units), digits), unit


def magnitude(value: float | None, kind: str, units, digits: int = SIGNIFICANT) -> str:
    """An SI value in its display unit, without the unit ("—" when None)."""
    return display(value, kind, units, digits)[0]


def with_unit(value: float | None, kind: str, units, digits: int = SIGNIFICANT) -> str:
    """``"645 lbf"``: an SI value in its display unit, with the unit ("—" when None)."""
    if value is None:
        return "—"
    text, unit = display(value, kind, units, digits)
    return f"{text} {unit}".strip()


def typed(text: str | None, value: float | None, kind: str, units,
          digits: int = SIGNIFICANT) -> tuple[str, str]:
    """(number, unit) of a value typed in the spec: its own digits when it was typed in the
    display unit (or is a bare number), otherwise converted like any other value."""
    if text and value is not None:
        magnitude, _, written = text.strip().partition(" ")
        unit = unit_of(kind, units)
        if written.strip() == (unit or "") and magnitude:
            return magnitude, pretty(unit or "")
    return display(value, kind, units, digits)


#: SI symbols of a compound unit that are shown in the campaign's display unit of their kind
#: (seconds stay seconds inside a compound: N·s/m, s/m).
_COMPOUND_KINDS = {"N": "force", "m": "length", "Pa": "pressure", "J": "energy", "kg": "mass"}


def compound_unit(si_unit: str, units) -> str:
    """A compound SI unit (``N*s^2/m^2``, ``N/m``) with each of its SI symbols replaced by
    the campaign's display unit of that kind (``kgf*s^2/mm^2``)."""
    def replaced(match):
        display_unit = getattr(units, _COMPOUND_KINDS[match.group(0)])
        return f"({display_unit})" if re.search(r"[*/^ ]", display_unit) else display_unit
    return re.sub(r"(?<![A-Za-z])(N|m|Pa|J|kg)(?![A-Za-z])", replaced, si_unit)


def parameter(value: float, si_unit: str, units, digits: int = SIGNIFICANT
              ) -> tuple[str, str]:
    """(number, unit) of a model parameter held in ``si_unit``: in the display unit of its
    kind where the unit names one, a compound unit in the display units of its parts
    (N·s²/m² in kgf·s²/mm² for a campaign in kgf and mm), "" for a ratio."""
    kind = KIND_OF_SI_UNIT.get(si_unit)
    if kind is not None:
        return display(value, kind, units, digits)
    if si_unit in ("1", ""):
        return number(value, digits), ""
    target = compound_unit(si_unit.replace("·", "*").replace("²", "^2").replace("³", "^3"),
                           units)
    try:
        return number(convert(value, si_unit.replace("·", "*").replace("²", "^2")
                              .replace("³", "^3"), target), digits), pretty(target)
    except Exception:   # noqa: BLE001 - a unit pint cannot convert is shown in SI
        return number(value, digits), pretty(si_unit)


def _decimals(reference: float, digits: int = SIGNIFICANT) -> int:
    """Decimal places of ``reference`` shown to ``digits`` significant figures."""
    if reference == 0 or not math.isfinite(reference):
        return digits - 1
    return digits - 1 - math.floor(math.log10(abs(reference)))


def fixed(value: float, decimals: int) -> str:
    """``value`` rounded to ``decimals`` places (negative: tens, hundreds), no '-0'."""
    if decimals >= 0:
        text = f"{value:.{decimals}f}"
    else:
        step = 10.0 ** (-decimals)
        text = f"{round(value / step) * step:.0f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def margin(value: float | None, limit: float | None, kind: str, units) -> str:
    """A margin in display units, to the limit's last shown digit, and in % of the limit.

    ``value`` is the margin (SI, positive when the criterion holds), ``limit`` the SI
    limit it is measured from.
    """
    if value is None:
        return "—"
    unit = pretty(unit_of(kind, units) or "")
    shown = to_display(value, kind, units)
    if limit is None or limit == 0:
        return f"{number(shown)} {unit}".strip()
    text = fixed(shown, _decimals(to_display(limit, kind, units)))
    if float(text) == 0 and abs(value) > EQUALITY_TOLERANCE * abs(limit):
        # a real margin finer than the limit's last shown digit keeps its sign and size
        text = number(shown, 2)
    if not text.startswith("-") and float(text.replace("×10", "e").translate(_PLAIN)) != 0:
        text = "+" + text
    share = fixed(100.0 * value / abs(limit), 2)
    if float(share) == 0 and abs(value) > EQUALITY_TOLERANCE * abs(limit):
        share = number(100.0 * value / abs(limit), 2)
    if not share.startswith("-") and float(share.replace("×10", "e").translate(_PLAIN)) != 0:
        share = "+" + share
    return f"{text} {unit}".strip() + f" ({share} %)"


def percent(fraction: float | None, digits: int = 1, signed: bool = False) -> str:
    """A fraction as a percentage with ``digits`` decimals ("—" when not finite)."""
    if fraction is None or not math.isfinite(fraction):
        return "—"
    return f"{100.0 * fraction:{'+' if signed else ''}.{digits}f} %"
