"""The typed values a campaign spec is made of: quantities with their units, dates,
identifiers and the strict base of every spec block.

A quantity is typed as a string with its unit ("12.5 in", "650 cm^3") and parsed by pint
into SI (:mod:`certkit.units`); a bare number is accepted only where the kind is
dimensionless.  The spec's blocks (:mod:`certkit.spec.schema` and the modules it gathers)
are built from these.
"""

from __future__ import annotations

import calendar
import datetime as dt
import math
import re
from typing import Annotated

from pydantic import (BaseModel, BeforeValidator, ConfigDict, Field, PlainSerializer,
                      PlainValidator, WithJsonSchema)
from pydantic_core import PydanticCustomError

from certkit.errors import shown
from certkit.units import (QuantityError, SpecQuantity, example_unit, kind_phrase, parse_quantity,
                           parse_unit)


def quantity(kind: str, description: str | None = None, minimum: float | None = 0.0,
              exclusive: bool = False, maximum: float | None = None):
    """Annotated type of a quantity of ``kind``; by default it may not be negative.

    ``exclusive`` makes the minimum strict (the quantity must be positive).
    """
    def validate(value):
        try:
            quantity = parse_quantity(value, kind)
        except QuantityError as exc:
            raise PydanticCustomError("quantity", str(exc)) from None
        low_bad = minimum is not None and (quantity.si <= minimum if exclusive
                                           else quantity.si < minimum)
        if low_bad:
            bound = f"{math.degrees(minimum):g} deg" if kind == "angle" else f"{minimum:g}"
            word = "positive" if exclusive and minimum == 0 else (
                "zero or more" if minimum == 0 else f"above {bound}" if exclusive
                else f"at least {bound}")
            raise PydanticCustomError("quantity", f"must be {word}, got {shown(quantity.text)}")
        if maximum is not None and quantity.si > maximum:
            limit = (f"{math.degrees(maximum):g} deg" if kind == "angle"
                     else f"{maximum:g}{' (100 %)' if maximum == 1 else ''}")
            raise PydanticCustomError("quantity", f"must be at most {limit}, got "
                                                  f"{shown(quantity.text)}")
        return quantity

    if kind == "dimensionless":
        schema = {"anyOf": [{"type": "number"}, {"type": "string"}],
                  "description": description or "a number (or a percentage such as '10 %')"}
    else:
        schema = {"type": "string",
                  "description": description or f"{kind_phrase(kind)} with its unit, "
                                                 f"e.g. '1 {example_unit(kind)}'"}
    return Annotated[SpecQuantity, PlainValidator(validate),
                     PlainSerializer(lambda q: q.text, return_type=str),
                     WithJsonSchema(schema)]


def unit_text(kind: str):
    def validate(value):
        if not isinstance(value, str):
            raise PydanticCustomError("unit", f"expected a unit of {kind} as text, got "
                                              f"{shown(value)}")
        try:
            return parse_unit(re.sub(r"\s*([*/·^])\s*", r"\1", value.strip()), kind)
        except QuantityError as exc:
            raise PydanticCustomError("unit", str(exc)) from None

    return Annotated[str, PlainValidator(validate),
                     WithJsonSchema({"type": "string", "description": f"a unit of {kind}"})]


Length = quantity("length")
PositiveLength = quantity("length", exclusive=True)
Area = quantity("area", exclusive=True)
Volume = quantity("volume", exclusive=True)
Mass = quantity("mass", exclusive=True)
#: a mass that may be zero (an unsprung mass declared negligible: the load measured is the
#: strut's force)
NonNegativeMass = quantity("mass")
Force = quantity("force")
Weight = quantity("weight", exclusive=True)
Pressure = quantity("pressure", exclusive=True)
Energy = quantity("energy")
Frequency = quantity("frequency", exclusive=True)
Inclination = quantity("angle", "strut axis from vertical, e.g. '3 deg' (at most 45 deg)",
                        minimum=-math.pi / 4, maximum=math.pi / 4)
Density = quantity("density", exclusive=True)
Stiffness = quantity("stiffness", exclusive=True)
Damping = quantity("damping")
Duration = quantity("time", exclusive=True)
WingLoading = quantity("wing_loading", "a wing loading (force per area), e.g. '10.15 lbf/ft^2'",
                        exclusive=True)
PositiveNumber = quantity("dimensionless", exclusive=True)
Fraction = quantity("dimensionless", "a fraction between 0 and 1, e.g. 0.667 or '10 %'",
                     maximum=1.0)


#: Years a date in a campaign may carry: a test from the first powered flights to well past
#: any report certkit will write; a year outside is a typing slip (0224, 20224).
YEARS = (1900, 2200)


def _date(value):
    """A date written YYYY-MM-DD (the ISO 8601 calendar date, extended form, and no other
    ISO form: not 20240115, not 2024-W03-1), in a year of :data:`YEARS`; one written in
    that form whose month or day does not exist is refused saying so (February 2025 has 28
    days)."""

    if isinstance(value, dt.date) and not isinstance(value, dt.datetime):
        date = value
    elif isinstance(value, str) and re.fullmatch(r"\d{4}-\d{2}-\d{2}", value.strip(),
                                                 re.ASCII):
        text = value.strip()
        year, month, day = (int(part) for part in text.split("-"))
        try:
            date = dt.date(year, month, day)
        except ValueError:
            if year == 0:
                why = "there is no year 0000 (the first is 0001)"
            elif not 1 <= month <= 12:
                why = f"there is no month {month:02d} (months are 01 to 12)"
            else:  # month names written out: calendar.month_name follows the locale
                name = ("January", "February", "March", "April", "May", "June", "July",
                        "August", "September", "October", "November", "December")[month - 1]
                why = f"{name} {year} has {calendar.monthrange(year, month)[1]} days"
            raise PydanticCustomError("date", f'"{text}" is not a date: {why}') from None
    else:
        raise PydanticCustomError("date", f"expected a date as YYYY-MM-DD, got {shown(value)}")
    if not YEARS[0] <= date.year <= YEARS[1]:
        raise PydanticCustomError("date", f'expected a date in a year from {YEARS[0]} to '
                                          f'{YEARS[1]}, got "{date.isoformat()}"')
    return date


Date = Annotated[dt.date, BeforeValidator(_date)]


def _clock_time(value) -> str:
    """A local time of day written HH:MM (00:00 to 23:59).  YAML 1.1 reads an unquoted
    14:05 as the base-60 number 845, so a number is refused asking for quotes."""
    if isinstance(value, str):
        text = value.strip()
        hours, _, minutes = text.partition(":")
        if (len(hours) == 2 and len(minutes) == 2 and (hours + minutes).isascii()
                and (hours + minutes).isdigit() and int(hours) < 24 and int(minutes) < 60):
            return text
        raise PydanticCustomError("time", f"expected a time of day as HH:MM (00:00 to "
                                          f"23:59), got {shown(text)}")
    if isinstance(value, int) and not isinstance(value, bool):
        raise PydanticCustomError(
            "time", f"expected a time of day as HH:MM in quotes; YAML read an unquoted time "
                    f"as the number {value}: write it as \"{value // 60:02d}:{value % 60:02d}\"")
    raise PydanticCustomError("time", f"expected a time of day as HH:MM, got {shown(value)}")


ClockTime = Annotated[str, BeforeValidator(_clock_time)]

Identifier = Annotated[str, Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.\-]*$", max_length=64)]
Text = Annotated[str, Field(min_length=1)]


class SpecBlock(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)
