"""The campaign spec's ``uncertainty`` block: the measurement uncertainties a lab states
(per recorded channel: the error of its gain and of its zero; per scalar input: the drop
height, the drop mass, the static weight, the wing area), where each comes from (a
certificate, or an assumed typical class), and the decision rule of the statements of
conformity (ISO/IEC 17025:2017 §7.8.6; ILAC-G8:09/2019).

Each uncertainty is a certificate's expanded uncertainty U with its coverage factor k (a
normal distribution, u = U/k, JCGM 100:2008 §4.3.3) or the half-width a of a rectangular or
triangular one (a tolerance, a resolution: u = a/√3 or a/√6, JCGM 100 §4.3.7, §4.3.9).
:mod:`certkit.compliance.verdict_uncertainty` propagates them.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal, Union

from pydantic import (Field, PlainSerializer, PlainValidator, WithJsonSchema, field_validator,
                      model_validator)
from pydantic_core import PydanticCustomError

from certkit.errors import shown
from certkit.spec.types import Fraction, Identifier, PositiveNumber, SpecBlock, Text
from certkit.units import QuantityError, SpecQuantity, kind_phrase, parse_quantity

#: The recorded channels an uncertainty can be stated for, with the kind of their zero offset.
UNCERTAIN_CHANNELS = {"vertical_load": "weight", "strut_stroke": "length",
                      "tyre_deflection": "length", "drop_mass_acceleration": "acceleration"}
#: The scalar inputs an uncertainty can be stated for, with their kind (or a share: "0.1 %").
UNCERTAIN_INPUTS = {"drop_height": "length", "drop_mass": "mass", "static_weight": "weight",
                    "wing_area": "area"}


#: The largest share of the reading an uncertainty may be: beyond it a gain error could
#: reach −100 % (a reading of nothing) within a few standard uncertainties.
MAX_SHARE = 0.2
#: The largest standard uncertainty as a share of the reading (U/k, a/√3, a/√6).
MAX_STANDARD_SHARE = 0.1


def _spread(kind: str, relative: str):
    """Annotated type of an uncertainty's size: a quantity of ``kind`` (absolute) or a share
    such as "0.5 %" (relative); ``relative`` is "required", "allowed" or "forbidden".  The
    SpecQuantity's unit is "1" for a share."""
    def validate(value):
        if isinstance(value, (bool, int, float)):
            raise PydanticCustomError("uncertainty", f"a bare number is ambiguous here: write a "
                                                     f"share of the reading with '%' (such as "
                                                     f"'0.5 %') or {kind_phrase(kind)} with "
                                                     f"its unit, got {shown(value)}")
        share = isinstance(value, str) and value.strip().endswith("%")
        if share and relative == "forbidden":
            raise PydanticCustomError("uncertainty", f"expected {kind_phrase(kind)} with its "
                                                     f"unit (an absolute uncertainty), got "
                                                     f"{shown(value)}")
        if not share and relative == "required":
            raise PydanticCustomError("uncertainty", f"expected a share of the reading such as "
                                                     f"'0.5 %', got {shown(value)}")
        try:
            parsed = parse_quantity(value, "dimensionless" if share else kind)
        except QuantityError as exc:
            raise PydanticCustomError("uncertainty", str(exc)) from None
        if not (math.isfinite(parsed.si) and parsed.si >= 0):
            raise PydanticCustomError("uncertainty", f"an uncertainty must be zero or more, "
                                                     f"got {shown(value)}")
        if share and parsed.si > MAX_SHARE:
            raise PydanticCustomError("uncertainty", f"an uncertainty of more than "
                                                     f"{100 * MAX_SHARE:g} % of the reading is "
                                                     f"no calibration, got {shown(value)}")
        return parsed

    share_text = "a share of the reading such as '0.5 %'"
    what = {"required": share_text, "forbidden": f"{kind_phrase(kind)} with its unit"}.get(
        relative, f"{kind_phrase(kind)} with its unit, or {share_text}")
    return Annotated[SpecQuantity, PlainValidator(validate),
                     PlainSerializer(lambda q: q.text, return_type=str),
                     WithJsonSchema({"anyOf": [{"type": "number"}, {"type": "string"}],
                                     "description": what})]


def _part(kind: str, relative: str, name: str):
    """A class for one uncertainty component of ``kind``: a certificate's expanded
    uncertainty U with its coverage factor k (a normal distribution, u = U/k, JCGM 100
    §4.3.3), or the half-width a of a rectangular or triangular distribution (a tolerance,
    a resolution; u = a/√3 or a/√6, JCGM 100 §4.3.7, §4.3.9)."""
    spread_type = _spread(kind, relative)

    class Part(SpecBlock):
        """One uncertainty component: a certificate's expanded uncertainty U with its coverage
        factor k, or the half-width a of a rectangular or triangular distribution."""

        expanded: spread_type | None = Field(None, description="expanded uncertainty U (normal)")
        k: PositiveNumber | None = Field(None, description="coverage factor of U (normal)")
        half_width: spread_type | None = Field(None, description="half-width a (rectangular or "
                                                           "triangular)")
        distribution: Literal["normal", "rectangular", "triangular"] = Field(
            "normal", description="normal: give expanded and k (u = U/k); rectangular or "
                                  "triangular: give half_width (u = a/√3 or a/√6)")

        @model_validator(mode="after")
        def _consistent(self):
            if self.distribution == "normal":
                if self.expanded is None or self.k is None or self.half_width is not None:
                    raise PydanticCustomError(
                        "uncertainty", "a normal distribution takes 'expanded' (U) and 'k' "
                                       "(its coverage factor), not 'half_width'")
            elif self.half_width is None or self.expanded is not None or self.k is not None:
                raise PydanticCustomError(
                    "uncertainty", f"a {self.distribution} distribution takes 'half_width', "
                                   f"not 'expanded' or 'k'")
            if self.spread.unit == "1":
                divisor = {"normal": self.k.si if self.k else 1.0, "rectangular": math.sqrt(3),
                           "triangular": math.sqrt(6)}[self.distribution]
                if self.spread.si / divisor > MAX_STANDARD_SHARE:
                    raise PydanticCustomError(
                        "uncertainty", f"a standard uncertainty of more than "
                                       f"{100 * MAX_STANDARD_SHARE:g} % of the reading is no "
                                       f"calibration: {self.spread.text} at this distribution "
                                       f"gives {100 * self.spread.si / divisor:.3g} %")
            return self

        @property
        def spread(self) -> SpecQuantity:
            return self.expanded if self.distribution == "normal" else self.half_width

    Part.__name__ = Part.__qualname__ = name
    return Part


GainPart = _part("dimensionless", "required", "GainPart")
_OFFSET_PARTS = {kind: _part(kind, "forbidden", f"{kind.title()}OffsetPart")
                 for kind in sorted(set(UNCERTAIN_CHANNELS.values()))}
_INPUT_PARTS = {name: _part(kind, "allowed", f"{name.title().replace('_', '')}Part")
                for name, kind in UNCERTAIN_INPUTS.items()}


class Provenance(SpecBlock):
    """Where a stated uncertainty comes from."""

    basis: Literal["certificate", "assumed"] = Field(
        description="certificate: from a calibration certificate or weighing record; assumed: "
                    "a typical class, stated as an assumption")
    source: Text = Field(description="the certificate's reference, or what the assumed figure "
                                     "rests on")


def _channel_class(channel: str, kind: str):
    """The calibration uncertainty of one recorded channel: the error of its gain (a share of
    the reading) and of its zero (in the channel's unit); one or both."""
    offset_part = _OFFSET_PARTS[kind]

    class ChannelUncertainty(Provenance):
        """The calibration uncertainty of one recorded channel, its gain and its zero, with
        where it comes from."""

        # Annotated, not "= Field(...)": a value named channel here would hide the argument
        # the annotation names
        channel: Annotated[Literal[channel], Field(  # type: ignore[valid-type]
            description="the recorded channel: vertical_load, strut_stroke, tyre_deflection or "
                        "drop_mass_acceleration")]
        gear_units: list[Identifier] | None = Field(
            None, description="the gear units whose channel this is (default: every unit; "
                              "not for drop_mass_acceleration)")
        gain: GainPart | None = Field(  # type: ignore[valid-type]
            None, description="the error of the channel's gain, a share of the reading")
        offset: offset_part | None = Field(  # type: ignore[valid-type]
            None, description="the error of the channel's zero, in the channel's own kind "
                              "(a force, length or acceleration)")

        @model_validator(mode="after")
        def _stated(self):
            if self.gain is None and self.offset is None:
                raise PydanticCustomError("uncertainty", "state the channel's 'gain' or "
                                                         "'offset' uncertainty (or both)")
            if self.channel == "drop_mass_acceleration" and self.gear_units is not None:
                raise PydanticCustomError("uncertainty", "the drop-mass acceleration belongs "
                                                         "to no gear unit: leave out "
                                                         "'gear_units'")
            return self

    name = "".join(word.title() for word in channel.split("_")) + "Uncertainty"
    ChannelUncertainty.__name__ = ChannelUncertainty.__qualname__ = name
    return ChannelUncertainty


_CHANNEL_CLASSES = tuple(_channel_class(channel, kind)
                         for channel, kind in UNCERTAIN_CHANNELS.items())
ChannelUncertainty = Annotated[Union[_CHANNEL_CLASSES], Field(discriminator="channel")]


def _input_field(name: str):
    class InputUncertainty(_INPUT_PARTS[name], Provenance):
        """The uncertainty of one scalar input, the same for every run or unit, with where
        it comes from."""
    InputUncertainty.__name__ = InputUncertainty.__qualname__ = (
        f"{name.title().replace('_', '')}Uncertainty")
    return InputUncertainty


class InputUncertainties(SpecBlock):
    """The uncertainties of the scalar inputs: each the same for every run or unit."""

    drop_height: _input_field("drop_height") | None = Field(  # type: ignore[valid-type]
        None, description="the free drop height as set and measured on the rig")
    drop_mass: _input_field("drop_mass") | None = Field(  # type: ignore[valid-type]
        None, description="the drop mass (scale)")
    static_weight: _input_field("static_weight") | None = Field(  # type: ignore[valid-type]
        None, description="each gear unit's static weight (aircraft weighing)")
    wing_area: _input_field("wing_area") | None = Field(  # type: ignore[valid-type]
        None, description="the wing area")


class UncertaintySpec(SpecBlock):
    """Measurement uncertainty and the decision rule of the statements of conformity
    (ISO/IEC 17025:2017 §7.8.6; ILAC-G8:09/2019)."""

    decision_rule: Literal["simple", "guarded", "probability"] = Field(
        "simple", description="simple acceptance (the default), guarded acceptance with the "
                              "guard band w = guard_factor·U, or a required conformance "
                              "probability")
    guard_factor: PositiveNumber = Field(parse_quantity(1, "dimensionless"),
                                         description="r of the guard band w = r·U")
    required_probability: Fraction = Field(parse_quantity("95 %", "dimensionless"),
                                           description="the conformance probability a "
                                                       "'probability' rule requires")
    coverage_probability: Fraction = Field(parse_quantity("95 %", "dimensionless"),
                                           description="coverage probability of the expanded "
                                                       "uncertainties reported")
    channels: list[ChannelUncertainty] = Field(
        [], description="the calibration uncertainties of the recorded channels, one entry per "
                        "channel (and gear units)")
    inputs: InputUncertainties = Field(
        InputUncertainties(), description="the uncertainties of the drop height, drop mass, "
                                          "static weight and wing area")

    @field_validator("required_probability", "coverage_probability")
    @classmethod
    def _probability(cls, value):
        if not 0.5 <= value.si < 1.0:
            raise PydanticCustomError("uncertainty", f"must lie in [50 %, 100 %), got "
                                                     f"{value.text}")
        return value
