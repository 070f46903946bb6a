"""A metering pin: the orifice area as a function of stroke, from a table."""

from __future__ import annotations

from dataclasses import dataclass

from certkit.errors import CertkitInputError
from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import Term, orifice_coefficient
from certkit.physics.effects.base import Effect


@dataclass(frozen=True)
class MeteringPin(Term):
    """Metering pin: orifice area varying with stroke, A_n(s) from a table (Currey 1988, metering pins).

    Replaces the nominal orifice's constant area: F_h = ρ·A_h³/(2·C_d²·A_n(s)²)·ṡ|ṡ|,
    A_n(s) linearly interpolated in the table (held constant beyond its ends).
    """

    strokes: tuple          # s_i [m], increasing
    areas: tuple            # A_n(s_i) [m^2]
    hydraulic_area: float   # A_h [m^2]
    nominal_area: float     # A_0, the nominal orifice's area [m^2] (for reference)
    discharge: float        # C_d
    density: float = 860.0  # ρ [kg/m^3]
    name = "metering pin"
    fields = (("strokes", "m", "stroke points of the area table"),
              ("areas", "m^2", "net orifice area at those strokes"),
              ("hydraulic_area", "m^2", "hydraulic area A_h"),
              ("nominal_area", "m^2", "area A_0 of the nominal orifice"),
              ("discharge", "1", "discharge coefficient C_d"),
              ("density", "kg/m^3", "oil density ρ"))

    def __post_init__(self):
        if not 2 <= len(self.strokes) == len(self.areas) <= dyn.PIN_POINTS:
            raise ValueError(f"a metering-pin table needs 2 to {dyn.PIN_POINTS} points, as many "
                             "areas as strokes")
        if any(b <= a for a, b in zip(self.strokes, self.strokes[1:])):
            raise ValueError("the metering-pin strokes must increase")
        if min(self.areas) <= 0:
            raise ValueError("the metering-pin areas must be positive")

    def pack(self, p):
        count = len(self.strokes)
        p[dyn.PIN], p[dyn.PIN_COUNT] = 1.0, count
        # K(s) = ρ·A_h³/(2·C_d²)/A_n(s)², the nominal orifice law with the table's area
        p[dyn.PIN_COEFFICIENT] = orifice_coefficient(self.hydraulic_area, 1.0, self.discharge,
                                                     self.density)
        p[dyn.PIN_STROKES:dyn.PIN_STROKES + count] = self.strokes
        p[dyn.PIN_AREAS:dyn.PIN_AREAS + count] = self.areas


def _build(gear) -> MeteringPin:
    pin, nominal = gear.unit.strut.metering_pin, gear.orifice
    strokes = tuple(q.si for q in pin.strokes)
    if (len(pin.strokes) != len(pin.areas) or len(pin.strokes) > dyn.PIN_POINTS
            or any(b <= a for a, b in zip(strokes, strokes[1:]))):
        raise CertkitInputError.single(
            gear.spec_file, None, f"gear_units[{gear.index}].strut.metering_pin",
            f"expected as many areas as strokes (at most {dyn.PIN_POINTS}), with the strokes "
            f"increasing; found {len(pin.strokes)} strokes and {len(pin.areas)} areas")
    return MeteringPin(strokes, tuple(q.si for q in pin.areas), nominal.hydraulic_area,
                       nominal.orifice_area, nominal.discharge, nominal.density)


EFFECT = Effect(label="metering pin", name="metering-pin", needs=(("strut", "metering_pin"),),
                build=_build)
