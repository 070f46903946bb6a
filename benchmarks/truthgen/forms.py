"""The truth forms the independent drop simulator can add to a gear: what the blind check
withholds from the diagnosis.

Every form is written here from its own literature, not from certkit's force laws, and
differs from the diagnosis's candidate families on purpose (a real gear's effect never
has the candidate's exact shape).  ``effect`` is the name of the library effect the form
belongs to, as certkit's diagnosis names it, or None for an effect outside the library
(abstaining is the right answer).  ``sizes`` is the range of the form's size parameter
over which the battery looks for a given effect/noise ratio; the effect grows
monotonically with the size.

Every form also has shape parameters (``shape``: the values the development battery uses,
which its description states) and the declared range each may be drawn from
(``shape_ranges``): a sealed battery draws its shapes there, so that the diagnosis is
scored on shapes it was not tuned on.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Form:
    effect: str | None
    label: str
    description: str
    unit: str
    sizes: tuple[float, float]
    shape: tuple = ()            # (name, development value) pairs
    shape_ranges: tuple = ()     # (name, low, high) pairs: where a sealed battery draws


@dataclass(frozen=True)
class Truth:
    """One withheld effect: a form id of :data:`FORMS`, its size (in the form's unit) and
    its shape parameters ((name, value) pairs; a name left out has its development
    value)."""

    form: str
    size: float
    shape: tuple = ()

    def value(self, name: str) -> float:
        """A shape parameter's value: this truth's own, or the form's development value."""
        own = dict(self.shape)
        return float(own[name]) if name in own else float(dict(FORMS[self.form].shape)[name])


FORMS: dict[str, Form] = {
    "lugre": Form(
        "seal friction", "LuGre seal friction",
        "bristle model (Canudas de Wit et al., IEEE TAC 40(3), 1995): "
        "dz/dt = v − σ0·|v|·z/g(v), g(v) = Fc + (Fs − Fc)·exp(−(v/vs)²), "
        "F = σ0·z + σ2·v; Fs = 1.4·Fc, vs = 0.02 m/s, "
        "σ0 = Fc / 0.1 mm, σ2 = 0.15·Fc per m/s; size Fc", "N", (2.0, 2000.0),
        shape=(("static_ratio", 1.4), ("stribeck_speed", 0.02), ("bristle", 1e-4),
               ("viscous", 0.15)),
        shape_ranges=(("static_ratio", 1.1, 2.0), ("stribeck_speed", 0.005, 0.08),
                      ("bristle", 3e-5, 5e-4), ("viscous", 0.0, 0.4))),
    "dahl": Form(
        "seal friction", "Dahl seal friction",
        "Dahl's rate law (Dahl, Aerospace Corp. TOR-0158(3107-18)-1, 1968): "
        "dF/dx = σ·(1 − F·sgn(v)/Fc), σ = Fc / 0.3 mm; size Fc", "N", (2.0, 2000.0),
        shape=(("presliding", 3e-4),), shape_ranges=(("presliding", 5e-5, 1.5e-3),)),
    "tyre-bouc-wen": Form(
        "tyre hysteresis", "Bouc–Wen tyre loop of constant amplitude",
        "Bouc–Wen element in parallel with the tyre (Wen, ASCE J. Eng. Mech. 102(2), 1976), "
        "dw/dt = δ'·(1 − (0.5·sgn(δ'·w) + 0.5)·|w|/w0), w0 = 3 mm, force size·w/w0; size "
        "the loop's half-height", "N", (5.0, 5000.0),
        shape=(("w0", 3e-3), ("beta", 0.5)),
        shape_ranges=(("w0", 0.8e-3, 8e-3), ("beta", 0.2, 0.8))),
    "tyre-proportional": Form(
        "tyre hysteresis", "tyre loop proportional to the load",
        "the Bouc–Wen element above (w0 = 1.5 mm) scaled by the static tyre force: "
        "size·F_static(δ)·w/w0; size the loop's half-height as a share of the static force",
        "1", (0.002, 0.5), shape=(("w0", 1.5e-3), ("beta", 0.5)),
        shape_ranges=(("w0", 0.5e-3, 5e-3), ("beta", 0.2, 0.8))),
    "leg-above": Form(
        "leg flexibility", "flexible leg above the strut, with its own mass",
        "a 6 kg strut cylinder hung from the airframe by a spring of compliance size "
        "(m/N), 3 % critical damping; the 6 kg leave the upper mass", "m/N",
        (1e-8, 2e-5), shape=(("leg_mass", 6.0), ("damping_ratio", 0.03)),
        shape_ranges=(("leg_mass", 2.0, 15.0), ("damping_ratio", 0.005, 0.10))),
    "leg-axle": Form(
        "leg flexibility", "flexible axle between piston and wheel",
        "the wheel (60 % of the unsprung mass) on a spring of compliance size (m/N) "
        "below the piston rod, 3 % critical damping", "m/N", (1e-8, 2e-5),
        shape=(("wheel_share", 0.6), ("damping_ratio", 0.03)),
        shape_ranges=(("wheel_share", 0.35, 0.8), ("damping_ratio", 0.005, 0.10))),
    "bessel-delay": Form(
        "sensor lag", "4th-order Bessel filter and delay",
        "every recorded channel through a 4th-order Bessel low-pass of cutoff "
        "1/(2π·size) (delay-normalised: group delay size) and a pure delay of size/2; "
        "size in s", "s", (1e-5, 0.02), shape=(("order", 4), ("delay_share", 0.5)),
        shape_ranges=(("order", 2, 6), ("delay_share", 0.0, 1.0))),
    "butterworth-delay": Form(
        "sensor lag", "2nd-order Butterworth filter and delay",
        "every recorded channel through a 2nd-order Butterworth low-pass of cutoff "
        "1/(2π·size) and a pure delay of size/4; size in s", "s", (1e-5, 0.02),
        shape=(("order", 2), ("delay_share", 0.25)),
        shape_ranges=(("order", 1, 4), ("delay_share", 0.0, 1.0))),
    "blow-off": Form(
        "rebound orifice", "rebound valve with blow-off",
        "extra rebound damping size·K·v² up to a blow-off speed of 0.25 m/s, beyond which "
        "the extra force grows only linearly with speed (a spring-loaded relief valve); "
        "size dimensionless", "1", (0.003, 5.0), shape=(("blow_off_speed", 0.25),),
        shape_ranges=(("blow_off_speed", 0.08, 0.6),)),
    "linear-quadratic": Form(
        "rebound orifice", "linear and quadratic rebound damping",
        "extra rebound force size·K·(0.5·v² + 0.5·0.3 m/s·|v|); size dimensionless", "1",
        (0.003, 5.0), shape=(("linear_speed", 0.3), ("linear_share", 0.5)),
        shape_ranges=(("linear_speed", 0.1, 1.0), ("linear_share", 0.2, 0.8))),
    "gas-drift": Form(
        None, "gas-charge temperature drift",
        "the gas precharge rises by size (a share) per drop in sequence as the strut warms "
        "(Gay-Lussac's law at fixed volume)", "1", (1e-4, 0.2)),
    "crosstalk": Form(
        None, "load-cell crosstalk",
        "the recorded load carries size times the load itself 12 ms earlier (a neighbouring "
        "cell's force through a shared platform frame)", "1", (1e-4, 0.5),
        shape=(("delay", 0.012),), shape_ranges=(("delay", 0.004, 0.03),)),
    "gain-skew": Form(
        "load-cell gain", "load-cell gain with a channel skew",
        "the recorded load reads (1 + size) times the platform force and lags the other "
        "channels by a skew of 0.4 ms (an amplifier's gain error and its own group delay, "
        "ISO 376:2011 calibration class; a multiplexed logger's channel skew); size the "
        "gain error (a share)", "1", (1e-4, 0.3),
        shape=(("skew", 4e-4), ("sign", 1.0)),
        shape_ranges=(("skew", 5e-5, 9e-4), ("sign", -1.0, 1.0))),
}
