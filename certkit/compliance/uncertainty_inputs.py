"""The input quantities of the uncertainty budgets, read off the campaign spec, and the
campaign with a set of their errors taken out (what the engine recomputes for each
sensitivity and each Monte Carlo check).

Each stated uncertainty of the spec's ``uncertainty`` block is an input quantity whose
estimate is zero: the error of a channel's gain ε (a share: the recorded r = (1 + ε)·q + o
for the quantity q) and of its zero o, per gear unit, the same in every run (one instrument,
one calibration: a systematic error, correlated between runs by construction); the error of
the drop height and of the drop mass of each run (set and weighed per drop: independent
between runs); the error of each gear unit's static weight; the error of the wing area.  An
input the spec leaves out is "not stated": it is probed (a small error put in and taken out)
only to find which verdicts depend on it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from certkit.compliance.measures import GearMeasures, measure_gear
from certkit.compliance.uncertainty import Input
from certkit.spec.campaign import Campaign
from certkit.spec.uncertainty import UncertaintySpec
from certkit.units import SpecQuantity

#: Share of an unstated input's probe (gain: this share; zero: this share of the channel's
#: largest reading; a scalar: this share of its value) to find what depends on it.
PROBE = 1e-3
CHANNEL_WORDS = {"vertical_load": "vertical load", "strut_stroke": "strut stroke",
                 "tyre_deflection": "tyre deflection",
                 "drop_mass_acceleration": "drop-mass acceleration"}
SERIES = {"vertical_load": "load", "strut_stroke": "stroke", "tyre_deflection": "tyre"}
INPUT_WORDS = {"drop_height": "drop height", "drop_mass": "drop mass",
               "static_weight": "static weight", "wing_area": "wing area"}
_INPUT_KINDS = {"drop_height": "length", "drop_mass": "mass", "static_weight": "force",
                "wing_area": "area"}
#: The SI unit of an input's spread, by its display kind.
SI_UNIT = {"length": "m", "force": "N", "mass": "kg", "area": "m^2", "acceleration": "m/s^2",
           "ratio": "1"}
_CHANNEL_KINDS = {"vertical_load": "force", "strut_stroke": "length",
                  "tyre_deflection": "length", "drop_mass_acceleration": "acceleration"}


# --------------------------------------------------------------------------- inputs
@dataclass(frozen=True)
class Source:
    """One input quantity of the budgets (estimate 0: an error)."""

    key: str               # "vertical_load gain [left-main]", "drop_height [D300]"
    label: str             # in words, for the report
    target: tuple          # ("channel", channel, gear | None, "gain" | "offset") or
                           # ("input", name, run or gear id | None)
    relative: bool         # a share of the quantity (gain, or a scalar stated in %)
    kind: str              # display kind of the spread ("ratio" for a share)
    input: Input | None    # None: not stated (probed only)
    probe: float           # the step of a probe (stated: u; not stated: a small error)
    basis: str = ""        # certificate | assumed
    origin: str = ""       # the certificate's reference, or what the assumption rests on
    stated_as: str = ""    # "U = 0.5 % (k = 2, normal)" as typed

    @property
    def unit(self) -> str:
        """The SI unit of the input's spread ("1" for a share)."""
        return SI_UNIT[self.kind]


def _stated_as(part) -> str:
    if part.distribution == "normal":
        return f"U = {part.expanded.text} (k = {part.k.text}, normal)"
    return f"± {part.half_width.text} ({part.distribution})"


def _input_of(name: str, part) -> Input:
    spread = part.spread.si
    if part.distribution == "normal":
        return Input.expanded(name, 0.0, spread, part.k.si)
    return Input(name, 0.0, part.distribution, spread)


def sources(campaign: Campaign) -> list[Source]:
    """Every input quantity the campaign's verdicts can depend on, stated or not, in a fixed
    order: channels per gear unit (gain, then zero), the drop-mass acceleration, then the
    drop height and drop mass per run, the static weight per unit and the wing area."""
    spec = campaign.spec
    stated = spec.uncertainty or UncertaintySpec()
    by_channel: dict[tuple, object] = {}
    for item in stated.channels:
        gears = ([None] if item.channel == "drop_mass_acceleration"
                 else item.gear_units or [g.id for g in spec.gear_units])
        for gear in gears:
            by_channel[(item.channel, gear)] = item
    peaks = _channel_peaks(campaign)
    out = []
    channels = [(c, g.id) for g in spec.gear_units for c in SERIES]
    if peaks.get(("drop_mass_acceleration", None)) is not None:
        channels.append(("drop_mass_acceleration", None))
    for channel, gear in channels:
        if not peaks.get((channel, gear)):
            continue                       # never recorded, or all zero (the data-quality
            #                                audit speaks of it): nothing depends on it
        item = by_channel.get((channel, gear))
        where = f" [{gear}]" if gear else ""
        for part in ("gain", "offset"):
            given = getattr(item, part) if item is not None else None
            key = f"{channel} {part}{where}"
            label = (f"{CHANNEL_WORDS[channel]}{f' of {gear}' if gear else ''}: "
                     f"{'gain' if part == 'gain' else 'zero'}")
            probe = PROBE if part == "gain" else PROBE * peaks[(channel, gear)]
            kind = "ratio" if part == "gain" else _CHANNEL_KINDS[channel]
            if given is None:
                out.append(Source(key, label, ("channel", channel, gear, part),
                                  part == "gain", kind, None, probe))
            else:
                value = _input_of(key, given)
                out.append(Source(key, label, ("channel", channel, gear, part), part == "gain",
                                  kind, value, value.standard or probe, item.basis,
                                  item.source, _stated_as(given)))
    scalars = ([("drop_height", run.id) for run in spec.runs]
               + [("drop_mass", run.id) for run in spec.runs]
               + [("static_weight", g.id) for g in spec.gear_units] + [("wing_area", None)])
    for name, owner in scalars:
        given = getattr(stated.inputs, name)
        where = f" [{owner}]" if owner else ""
        label = f"{INPUT_WORDS[name]}{f' of {owner}' if owner else ''}"
        nominal = scalar(spec, name, owner).si
        if given is None:
            out.append(Source(f"{name}{where}", label, ("input", name, owner), True, "ratio",
                              None, PROBE))
            continue
        relative = given.spread.unit == "1"
        value = _input_of(f"{name}{where}", given)
        out.append(Source(f"{name}{where}", label, ("input", name, owner), relative,
                          "ratio" if relative else _INPUT_KINDS[name], value,
                          value.standard if value.standard > 0 else PROBE * (1 if relative
                                                                              else nominal),
                          given.basis, given.source, _stated_as(given)))
    return out


def _channel_peaks(campaign: Campaign) -> dict[tuple, float]:
    """(channel, gear) -> the largest magnitude recorded in any run (the size of a probe)."""
    peaks: dict[tuple, float] = {}
    for series in campaign.series.values():
        if series is None:
            continue
        for gear, channels in series.gears.items():
            for channel, attribute in SERIES.items():
                values = getattr(channels, attribute)
                if values is not None:
                    peak = float(np.max(np.abs(values)))
                    peaks[(channel, gear)] = max(peaks.get((channel, gear), 0.0), peak)
        if series.acceleration is not None:
            key = ("drop_mass_acceleration", None)
            peaks[key] = max(peaks.get(key, 0.0), float(np.max(np.abs(series.acceleration))))
    return peaks


def scalar(spec, name: str, owner: str | None) -> SpecQuantity:
    if name in ("drop_height", "drop_mass"):
        run = next(run for run in spec.runs if run.id == owner)
        return getattr(run, name)
    if name == "static_weight":
        return next(g for g in spec.gear_units if g.id == owner).static_weight
    return spec.aircraft.wing_area


# --------------------------------------------------------------------------- perturbed campaign
def perturbed(campaign: Campaign, changes: dict[int, float], items: list[Source]) -> Campaign:
    """``campaign`` with the errors ``changes`` (index into ``items`` -> the error's value)
    taken out of its inputs: a channel's recorded r becomes (r − o)/(1 + ε); a scalar x
    becomes x − e (or x·(1 − e) for a share).  Only the SI magnitudes change: the typed text,
    and so every stated resolution, stays."""
    spec = campaign.spec
    gains: dict[tuple, float] = {}
    offsets: dict[tuple, float] = {}
    scalars: dict[tuple, tuple[float, bool]] = {}
    for index, error in changes.items():
        item = items[index]
        if item.target[0] == "channel":
            _, channel, gear, part = item.target
            (gains if part == "gain" else offsets)[(channel, gear)] = error
        else:
            scalars[item.target[1:]] = (error, item.relative)

    def corrected(values, channel, gear):
        if values is None:
            return None
        gain, offset = gains.get((channel, gear), 0.0), offsets.get((channel, gear), 0.0)
        if gain == 0.0 and offset == 0.0:
            return values
        return (values - offset) / (1.0 + gain)

    def moved(quantity: SpecQuantity, name: str, owner) -> SpecQuantity:
        if (name, owner) not in scalars:
            return quantity
        error, relative = scalars[(name, owner)]
        si = quantity.si * (1.0 - error) if relative else quantity.si - error
        return replace(quantity, si=si)

    series = {}
    for run_id, run_series in campaign.series.items():
        if run_series is None:
            series[run_id] = None
            continue
        gears = {gear: type(channels)(**{attribute: corrected(getattr(channels, attribute),
                                                               channel, gear)
                                         for channel, attribute in SERIES.items()})
                 for gear, channels in run_series.gears.items()}
        series[run_id] = replace(run_series, gears=gears, acceleration=corrected(
            run_series.acceleration, "drop_mass_acceleration", None))
    runs = [run.model_copy(update={"drop_height": moved(run.drop_height, "drop_height", run.id),
                                   "drop_mass": moved(run.drop_mass, "drop_mass", run.id)})
            for run in spec.runs]
    units = [unit.model_copy(update={"static_weight": moved(unit.static_weight,
                                                             "static_weight", unit.id)})
             for unit in spec.gear_units]
    aircraft = spec.aircraft.model_copy(
        update={"wing_area": moved(spec.aircraft.wing_area, "wing_area", None)})
    new_spec = spec.model_copy(update={"runs": runs, "gear_units": units, "aircraft": aircraft})
    return replace(campaign, spec=new_spec, series=series)


class RepeatedMeasures:
    """:func:`~certkit.compliance.measures.measure_gear` that remembers its results for
    records it has read before.

    The probes of one assessment evaluate the campaign again with one input moved, and
    :func:`perturbed` keeps every record it does not change the very same array: a drop
    height, a mass or another gear's channel leaves a gear unit's records as they were,
    and reading them again would give the same measures.  A result is remembered under the
    identity of the arrays and the value of every other argument; the arrays are kept with
    it, so no other array can take their identity while it is remembered.  Meant for one
    assessment (the arrays are never modified in place)."""

    def __init__(self) -> None:
        self._seen: dict[tuple, tuple[GearMeasures, tuple]] = {}

    def __call__(self, time: np.ndarray, load: np.ndarray, stroke: np.ndarray | None,
                 tyre: np.ndarray | None, static_weight: float, inclination: float = 0.0,
                 unsprung_mass: float = 0.0) -> GearMeasures:
        records = (time, load, stroke, tyre)
        key = tuple(id(array) for array in records) + (static_weight, inclination,
                                                        unsprung_mass)
        if key not in self._seen:
            self._seen[key] = (measure_gear(time, load, stroke, tyre, static_weight,
                                            inclination, unsprung_mass), records)
        return self._seen[key][0]
