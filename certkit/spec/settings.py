"""The campaign spec's settings blocks: the data-quality audit's thresholds, the units the
report shows numbers in, and the drop model's settings (effects, sensor, calibration,
identification, gap diagnosis).

:mod:`certkit.spec.schema` assembles the whole spec from these and the other block modules.
"""

from __future__ import annotations

import re
from typing import Literal

from pydantic import Field, StrictInt, model_validator

from certkit.spec.types import (Force, Fraction, Frequency, Identifier, Length, PositiveNumber,
                                SpecBlock, Text, quantity, unit_text)
from certkit.units import parse_quantity


# --------------------------------------------------------------------------- audit
class AuditSettings(SpecBlock):
    """Thresholds of the data-quality audit, each named with its check in
    docs/audit-checklist.md; the report prints the values used."""

    asymmetry_threshold: Fraction = Field(
        parse_quantity("10 %", "dimensionless"),
        description="how far the left and right main units of one drop may differ in peak "
                    "load, stroke or tyre deflection, as a share of their mean, before a "
                    "warning")
    reported_tolerance: Fraction = Field(
        parse_quantity("2 %", "dimensionless"),
        description="how far a reported value (wing loading, required drop height, peak load, "
                    "stroke, deflection, energy) may differ from the one recomputed, and the "
                    "main units' static weights together exceed the maximum weight")
    energy_tolerance: Fraction = Field(
        parse_quantity("1 %", "dimensionless"),
        description="how far the absorbed energy may exceed the energy available "
                    "W_drop·(h + d) − L_dev·W_drop·d before an error")
    energy_sum_tolerance: Fraction = Field(
        parse_quantity("10 %", "dimensionless"),
        description="how far E_s + E_t, each to its own peak, may exceed the energy available; "
                    "also the main units together against the whole airplane's")
    reported_energy_spread: Fraction = Field(
        parse_quantity("15 %", "dimensionless"),
        description="how far the drop weight implied by the reported energies, as a share of "
                    "the weight dropped, may spread across a unit's runs before a warning")
    static_stroke_tolerance: Fraction = Field(
        parse_quantity("15 %", "dimensionless"),
        description="share of the static stroke seal friction and gas temperature may move it")
    tyre_curve_tolerance: Fraction = Field(
        parse_quantity("15 %", "dimensionless"),
        description="how far the peak load may fall below the tyre curve at maximum deflection")
    bottoming_margin: Fraction = Field(
        parse_quantity("5 %", "dimensionless"),
        description="a drop whose maximum stroke comes within this share of the design "
                    "stroke is near bottoming (a warning)")
    drop_mass_spread: Fraction = Field(
        parse_quantity("10 %", "dimensionless"),
        description="how far the drop weight the absorbed energy E_d implies may differ from "
                    "the weight dropped, and spread across runs, before a warning")
    sample_rate_tolerance: Fraction = Field(
        parse_quantity("1 %", "dimensionless"),
        description="how far a data file's sample rate (from its time steps) may differ from "
                    "the declared one before it is an input error (waivable: sample_rate)")
    load_consistency_tolerance: Fraction = Field(
        parse_quantity("10 %", "dimensionless"),
        description="how far n_j from the drop-mass accelerometer may differ from the "
                    "platform loads' max ΣF_V/W_drop + L_dev before a warning")
    zero_travel_tolerance: Length = Field(
        parse_quantity("1 mm", "length"),
        description="how far stroke and tyre deflection may read from zero just before "
                    "touchdown before a warning, and the stroke go past the design stroke "
                    "before an error (a length)")


# --------------------------------------------------------------------------- display units
#: Display units of each unit system; a unit not given in report.units comes from here.
UNIT_SYSTEMS = {
    "SI": {"length": "mm", "force": "N", "mass": "kg", "energy": "J", "velocity": "m/s",
           "pressure": "kPa", "area": "m^2", "wing_loading": "N/m^2", "time": "ms"},
    "US": {"length": "in", "force": "lbf", "mass": "lb", "energy": "ft*lbf", "velocity": "ft/s",
           "pressure": "psi", "area": "ft^2", "wing_loading": "lbf/ft^2", "time": "ms"},
}
_US_LENGTHS = {"in", "inch", "inches", "ft", "foot", "feet", "yd", "yard", "mil", "thou"}
_US_UNITS = _US_LENGTHS | {"lbf", "lb", "lbs", "pound", "pounds", "psi", "ksi", "mph", "kip",
                           "slug", "ozf", "oz"}


def _is_us(unit: object) -> bool:
    """Whether a unit text names a US customary unit (in, ft, lbf, psi, ...)."""
    return isinstance(unit, str) and bool(set(re.split(r"[\s*/·^0-9+\-]+", unit)) & _US_UNITS)


def _shown_in(kind: str, what: str) -> str:
    """The description of a display-unit key: what it shows, and its default per system."""
    si, us = UNIT_SYSTEMS["SI"][kind], UNIT_SYSTEMS["US"][kind]
    default = f"{si} in both systems" if si == us else f"SI: {si}, US: {us}"
    return f"unit of the {what} shown (default {default})"


class DisplayUnits(SpecBlock):
    """The units every number a person reads is shown in.

    A unit not given follows ``system``; without ``system``, the system of the length unit
    (US customary for in or ft, else SI), or without a length unit the system of the units
    given, so ``{length: in, force: lbf}`` and ``{force: lbf}`` show areas in ft^2 and
    energies in ft*lbf.
    """

    system: Literal["SI", "US"] | None = Field(
        None, description="unit system of the units not given (default: the length unit's)")
    length: unit_text("length") = Field(  # type: ignore[valid-type]
        "mm", description=_shown_in("length", "lengths"))
    force: unit_text("weight") = Field(  # type: ignore[valid-type]
        "N", description=_shown_in("force", "forces"))
    mass: unit_text("mass") = Field(  # type: ignore[valid-type]
        "kg", description=_shown_in("mass", "masses"))
    energy: unit_text("energy") = Field(  # type: ignore[valid-type]
        "J", description=_shown_in("energy", "energies"))
    velocity: unit_text("velocity") = Field(  # type: ignore[valid-type]
        "m/s", description=_shown_in("velocity", "velocities"))
    pressure: unit_text("pressure") = Field(  # type: ignore[valid-type]
        "kPa", description=_shown_in("pressure", "pressures"))
    area: unit_text("area") = Field(  # type: ignore[valid-type]
        "m^2", description=_shown_in("area", "areas"))
    wing_loading: unit_text("wing_loading") = Field(  # type: ignore[valid-type]
        "N/m^2", description=_shown_in("wing_loading", "wing loadings"))
    time: unit_text("time") = Field(  # type: ignore[valid-type]
        "ms", description=_shown_in("time", "times"))

    @model_validator(mode="before")
    @classmethod
    def _fill_from_system(cls, data):
        if not isinstance(data, dict):
            return data
        system = data.get("system")
        if system not in UNIT_SYSTEMS:
            given = [data["length"]] if "length" in data else list(data.values())
            system = "US" if any(_is_us(unit) for unit in given) else "SI"
        return {**UNIT_SYSTEMS[system], **data}


class ReportSettings(SpecBlock):
    """How the report shows its numbers."""

    units: DisplayUnits = Field(
        DisplayUnits(), description="the units of every number a person reads (results.json "
                                    "and the tables keep SI)")


# --------------------------------------------------------------------------- drop model
#: The effects a campaign can switch on: the names of certkit.physics.effects' registry (kept
#: here so a spec validates without the physics; tests/test_effect_registry.py holds the two
#: equal).
Effect = Literal["seal-friction", "rebound-orifice", "metering-pin", "tyre-hysteresis",
                 "heat-transfer", "oil-compressibility", "leg-flexibility",
                 "platform-compliance", "sensor-dynamics", "load-cell-gain"]


class SensorSpec(SpecBlock):
    """Low-pass and delay of the recorded channels (effect 'sensor-dynamics'): `certkit
    simulate` applies them to the simulated channels, as the logger would record them."""

    cutoff: Frequency = Field(description="cut-off of the Butterworth low-pass (a frequency)")
    order: int = Field(2, ge=1, le=8, description="order of the Butterworth low-pass")
    delay: quantity("time") = Field(  # type: ignore[valid-type]
        parse_quantity("0 s", "time"),
        description="pure delay after the low-pass, such as channel skew or transducer lag (a "
                    "time)")


CalibrationParameter = Literal[
    "discharge-coefficient", "gas-precharge", "gas-volume", "polytropic-exponent",
    "tyre-stiffness", "tyre-exponent", "tyre-damping", "friction", "friction-pressure-factor",
    "rebound-damping", "load-cell-gain", "top-out-compression"]


class CalibrationSpec(SpecBlock):
    """What `certkit calibrate` fits (default: C_d, pre-charge, n, tyre stiffness and
    exponent, the top-out stop's compression, friction and load-cell gain when those are on),
    to which runs, and from how many further starts."""

    parameters: list[CalibrationParameter] = Field([], description="parameters to fit")
    runs: list[Identifier] = Field(
        [], description="runs to fit to (default: the drops the identification trains on: "
                        "every drop but those at the highest drop height, and the middle "
                        "height's when there are four heights or more); the others are "
                        "simulated to validate the calibrated model")
    starts: StrictInt = Field(
        0, ge=0, le=20,   # le: certkit.physics.starts.MOST_STARTS
        description="further starts of the fit, spread over the parameters' bounds "
                    "(Sobol's sequence: a fixed set of points); the best is kept when its "
                    "training cost is more than 0.1 % below the fit from the spec's values "
                    "(0: from the spec's values only; each start adds a fit of at most 60 "
                    "evaluations of the residuals with forward differences, and the best "
                    "start is fitted again in full)")


class BlockModelSpec(SpecBlock):
    """Orders and (optionally fixed) LS-SVM hyper-parameters of one identified model."""

    na: int = Field(ge=0, le=20, description="past outputs (denominator order)")
    nb: int = Field(ge=1, le=20, description="input terms (numerator terms)")
    gamma: PositiveNumber | None = Field(None, description="regularisation γ; default: tuned")
    sigma2: PositiveNumber | None = Field(
        None, description="RBF width σ² of K = exp(−‖x − z‖²/σ²); default: tuned")


class SmallSignalSpec(SpecBlock):
    """The seed's small-signal method (§4): first amplitude, scaling K, linearity tolerance."""

    amplitude: Force = Field(parse_quantity("500 N", "force"),
                             description="RMS of the first small random force (a force)")
    gain: PositiveNumber = Field(
        parse_quantity("2", "dimensionless"),
        description="K: each linearity check applies the force and K times it, and the "
                    "amplitude grows by K while the response stays linear")
    tolerance: Fraction = Field(
        parse_quantity("5 %", "dimensionless"),
        description="how far the response to K times the force may differ from K times the "
                    "response (relative, per output) for it to count as linear")


class IdentificationSpec(SpecBlock):
    """Identification settings; defaults follow the seed paper (6 poles, 4 input terms)."""

    hammerstein: BlockModelSpec = Field(
        BlockModelSpec(na=6, nb=4), description="orders and hyper-parameters of the Hammerstein "
                                                "model")
    wiener: BlockModelSpec = Field(
        BlockModelSpec(na=6, nb=4), description="orders and hyper-parameters of the Wiener model")
    narx: BlockModelSpec = Field(
        BlockModelSpec(na=2, nb=2), description="orders and hyper-parameters of the NARX model")
    held_out: list[Identifier] = Field(
        [], description="runs kept out of fitting and tuning (default: the highest drop)")
    small_signal: SmallSignalSpec = Field(
        SmallSignalSpec(), description="the small-signal method, which gives the Wiener "
                                       "model's linear block when no small-signal run is "
                                       "recorded")
    nonlinearity_target: Length = Field(
        parse_quantity("0.1 mm", "length"),
        description="step 9: the static nonlinearity's tuning stops once its cross-validated "
                    "RMSE is at or below this")


class GapSpec(SpecBlock):
    """Sim-to-real gap diagnosis (`certkit gap`, the report's gap section)."""

    held_out: list[Identifier] = Field(
        [], description="runs kept out of calibration, scoring and refits, only evaluated "
                        "(default: every drop at the highest drop height, and the middle "
                        "height's when there are four heights or more)")
    blind_check: Text | None = Field(
        None, description="the JSON file written by benchmarks/blind_independent.py "
                          "--battery development, relative to this spec file and inside its "
                          "folder; the report summarises it and "
                          "hashes it with the other inputs")
    sealed_blind_check: Text | None = Field(
        None, description="the record of the SEALED battery (benchmarks/blind_independent.py "
                          "--battery sealed), relative to this spec file and inside its "
                          "folder: the report gives its held-out figures beside the "
                          "development record's in-sample ones (model.gap.blind_check)")


class ModelSettings(SpecBlock):
    """The physics model used to simulate and calibrate: which optional effects are on."""

    effects: list[Effect] = Field([], description="optional effects switched on (default none)")
    sensor: SensorSpec | None = Field(None, description="the logger's low-pass and delay, for "
                                                        "the effect 'sensor-dynamics'")
    calibration: CalibrationSpec | None = Field(None, description="what the calibration fits, "
                                                                  "and to which runs")
    identification: IdentificationSpec = Field(
        IdentificationSpec(), description="the Hammerstein, Wiener and NARX identification")
    gap: GapSpec = Field(GapSpec(), description="the sim-to-real gap diagnosis")
