"""The truth forms the independent drop simulator can add to a gear: what the blind check
withholds from the diagnosis.

Every form is written here from its own literature, not from certkit's force laws, and
differs from the diagnosis's candidate families on purpose (a real gear's effect never
has the candidate's exact shape).  ``effect`` is the name of the library effect the form
belongs to, as certkit's diagnosis names it, or None for an effect outside the library
(abstaining is the right answer).  ``sizes`` is the range of the form's size parameter
over which the battery looks for a given effect/noise ratio; the effect grows
monotonically with the size.
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


@dataclass(frozen=True)
class Truth:
    """One withheld effect: a form id of :data:`FORMS` and its size (in the form's unit)."""

    form: str
    size: float


FORMS: dict[str, Form] = {
    "lugre": Form(
        "seal friction", "LuGre seal friction",
        "bristle model (Canudas de Wit et al., IEEE TAC 40(3), 1995): "
        "dz/dt = v − σ0·|v|·z/g(v), g(v) = Fc + (Fs − Fc)·exp(−(v/vs)²), "
        "F = σ0·z + σ2·v; Fs = 1.4·Fc, vs = 0.02 m/s, "
        "σ0 = Fc / 0.1 mm, σ2 = 0.15·Fc per m/s; size Fc", "N", (2.0, 2000.0)),
    "dahl": Form(
        "seal friction", "Dahl seal friction",
        "Dahl's rate law (Dahl, Aerospace Corp. TOR-0158(3107-18)-1, 1968): "
        "dF/dx = σ·(1 − F·sgn(v)/Fc), σ = Fc / 0.3 mm; size Fc", "N", (2.0, 2000.0)),
    "tyre-bouc-wen": Form(
        "tyre hysteresis", "Bouc–Wen tyre loop of constant amplitude",
        "Bouc–Wen element in parallel with the tyre (Wen, ASCE J. Eng. Mech. 102(2), 1976), "
        "dw/dt = δ'·(1 − (0.5·sgn(δ'·w) + 0.5)·|w|/w0), w0 = 3 mm, force size·w/w0; size "
        "the loop's half-height", "N", (5.0, 5000.0)),
    "tyre-proportional": Form(
        "tyre hysteresis", "tyre loop proportional to the load",
        "the Bouc–Wen element above (w0 = 1.5 mm) scaled by the static tyre force: "
        "size·F_static(δ)·w/w0; size the loop's half-height as a share of the static force",
        "1", (0.002, 0.5)),
    "leg-above": Form(
        "leg flexibility", "flexible leg above the strut, with its own mass",
        "a 6 kg strut cylinder hung from the airframe by a spring of compliance size "
        "(m/N), 3 % critical damping; the 6 kg leave the upper mass", "m/N",
        (1e-8, 2e-5)),
    "leg-axle": Form(
        "leg flexibility", "flexible axle between piston and wheel",
        "the wheel (60 % of the unsprung mass) on a spring of compliance size (m/N) "
        "below the piston rod, 3 % critical damping", "m/N", (1e-8, 2e-5)),
    "bessel-delay": Form(
        "sensor lag", "4th-order Bessel filter and delay",
        "every recorded channel through a 4th-order Bessel low-pass of cutoff "
        "1/(2π·size) (delay-normalised: group delay size) and a pure delay of size/2; "
        "size in s", "s", (1e-5, 0.02)),
    "butterworth-delay": Form(
        "sensor lag", "2nd-order Butterworth filter and delay",
        "every recorded channel through a 2nd-order Butterworth low-pass of cutoff "
        "1/(2π·size) and a pure delay of size/4; size in s", "s", (1e-5, 0.02)),
    "blow-off": Form(
        "rebound orifice", "rebound valve with blow-off",
        "extra rebound damping size·K·v² up to a blow-off speed of 0.25 m/s, beyond which "
        "the extra force grows only linearly with speed (a spring-loaded relief valve); "
        "size dimensionless", "1", (0.003, 5.0)),
    "linear-quadratic": Form(
        "rebound orifice", "linear and quadratic rebound damping",
        "extra rebound force size·K·(0.5·v² + 0.5·0.3 m/s·|v|); size dimensionless", "1",
        (0.003, 5.0)),
    "gas-drift": Form(
        None, "gas-charge temperature drift",
        "the gas precharge rises by size (a share) per drop in sequence as the strut warms "
        "(Gay-Lussac's law at fixed volume)", "1", (1e-4, 0.2)),
    "crosstalk": Form(
        None, "load-cell crosstalk",
        "the recorded load carries size times the load itself 12 ms earlier (a neighbouring "
        "cell's force through a shared platform frame)", "1", (1e-4, 0.5)),
}
