"""The force the calibrated nominal model misses, estimated from the records alone: a
model-free view of the gap.

On the first compression and rebound of each run (touchdown to the end of the rebound,
:mod:`certkit.gap.phases`), the strut and tyre force balances are inverted with the
measured motion:

- strut: the axial force the records imply, F_s = cos θ·(F_V − m2·(g − δ̈))
  (:func:`certkit.compliance.measures.strut_force`), less the calibrated nominal strut law
  at the measured stroke and stroke rate (gas spring, square-law damping, stops);
- tyre: the measured load less the calibrated nominal tyre law at the measured deflection
  and deflection rate.

No candidate effect enters: the two missing forces are what the records say the nominal
laws lack.  Their signatures are then read by least squares on a few shapes, each the
mark of an effect (a sign(ṡ) step: friction; a term in ṡ|ṡ| on extension only: rebound
damping; a loop in tyre deflection that scales with the static curve or has a constant
width: tyre hysteresis), beside shapes the nominal parameters could still absorb (a gas
stiffness, a damping in both directions, a tyre stiffness and damping), so that a
mis-calibration is not read as an effect.  Each shape's share is its partial R²: of what
the other shapes leave unexplained, the share it explains (1 − SSE(all)/SSE(all but it)).  Rates are
Savitzky-Golay derivatives over :data:`certkit.compliance.measures.AXLE_WINDOW`
(Savitzky & Golay, Anal. Chem. 36(8), 1964).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import savgol_filter

from certkit.compliance.measures import (AXLE_POLYORDER, AXLE_WINDOW, strut_force, touchdown_index,
                                         window_samples)
from certkit.gap.phases import segment
from certkit.physics import dynamics as dyn
from certkit.physics.gear_model import drop_model_for

#: Velocity scale of the sign(·) steps of the friction and tyre-loop shapes [m/s].
STEP_VELOCITY = 0.005
#: Deflection over which a constant tyre loop builds up [m].
LOOP_ONSET = 0.002
#: A shape counts as seen when it explains at least this share of a missing force's
#: variance (partial R²).
SEEN = 0.05


@dataclass(frozen=True)
class MissingForce:
    """One run's first compression and rebound: measured motion and the force the nominal
    laws miss (SI)."""

    run: str
    time: np.ndarray            # s from touchdown
    stroke: np.ndarray
    stroke_rate: np.ndarray
    tyre: np.ndarray
    tyre_rate: np.ndarray
    gas: np.ndarray             # the nominal gas force at the measured stroke [N]
    tyre_static: np.ndarray     # the nominal static tyre curve at the measured deflection [N]
    strut_missing: np.ndarray   # implied strut force − nominal strut law [N]
    tyre_missing: np.ndarray    # measured load − nominal tyre law [N]


@dataclass(frozen=True)
class Signature:
    """One shape fitted to a missing force: its coefficient and the share of the missing
    force's variance it alone explains."""

    force: str          # "strut" or "tyre"
    shape: str          # the shape in words
    effect: str | None  # the effect it marks (None: a shape the nominal parameters absorb)
    coefficient: float
    unit: str
    share: float        # partial R² (0-1)

    @property
    def seen(self) -> bool:
        return self.effect is not None and self.coefficient > 0 and self.share >= SEEN


def _rate(values: np.ndarray, step: float) -> np.ndarray:
    window = window_samples(AXLE_WINDOW, step, AXLE_POLYORDER + 2)
    if values.size <= window:
        return np.gradient(values, step)
    return savgol_filter(values, window, AXLE_POLYORDER, deriv=1, delta=step)


def missing_force(run_id: str, time: np.ndarray, load: np.ndarray, stroke: np.ndarray,
                  tyre: np.ndarray, model, static_weight: float) -> MissingForce | None:
    """The missing forces of one run (whole records, SI) under the calibrated nominal
    ``model`` (a :class:`~certkit.physics.drop_model.DropModel`); None when the run has
    no first compression and rebound to look at."""
    phases = {p.name: p for p in segment(time, load, stroke, static_weight)}
    contact = touchdown_index(load, static_weight)
    if contact is None or "rebound" not in phases:
        return None
    cut = slice(contact, phases["rebound"].stop)
    step = float(np.median(np.diff(time)))
    stroke_rate, tyre_rate = _rate(stroke, step), _rate(tyre, step)
    implied = strut_force(time, load, tyre, model.lower_mass, model.inclination)
    nominal_strut, gas, nominal_tyre, static = (np.empty(time.size) for _ in range(4))
    dyn.strut_and_tyre_forces(model.pack(), stroke, stroke_rate, tyre, tyre_rate,
                              nominal_strut, gas, nominal_tyre, static)
    return MissingForce(run_id, time[cut] - time[contact], stroke[cut], stroke_rate[cut],
                        tyre[cut], tyre_rate[cut], gas[cut], static[cut],
                        implied[cut] - nominal_strut[cut], load[cut] - nominal_tyre[cut])


def _shapes(force: MissingForce) -> dict:
    """Shape name -> (force, effect or None, unit, strut column, tyre column)."""
    v, d = force.stroke_rate, force.tyre_rate
    extending = v < 0.0
    step = np.tanh(v / STEP_VELOCITY)
    loop = np.tanh(d / STEP_VELOCITY)
    none = np.zeros(v.size)
    return {
        # strut: what re-tuning absorbs, then the effects' marks
        "gas stiffness (∝ stroke)": ("strut", None, "N/m", force.stroke),
        "offset": ("strut", None, "N", np.ones(v.size)),
        "damping both ways (ṡ|ṡ|)": ("strut", None, "N·s²/m²", v * np.abs(v)),
        "step with sign(ṡ)": ("strut", "seal friction", "N", step),
        "step ∝ gas force × sign(ṡ)": ("strut", "seal friction", "1", force.gas * step),
        "ṡ|ṡ| on extension only": ("strut", "rebound orifice", "N·s²/m²",
                                   np.where(extending, v * np.abs(v), none)),
        # tyre
        "tyre stiffness (∝ static curve)": ("tyre", None, "1", force.tyre_static),
        "tyre damping (∝ f(δ)·δ̇)": ("tyre", None, "s/m", force.tyre_static * d),
        "loop ∝ static curve × sign(δ̇)": ("tyre", "tyre hysteresis", "1",
                                            force.tyre_static * loop),
        "loop of constant width × sign(δ̇)": ("tyre", "tyre hysteresis", "N",
                                               (1 - np.exp(-np.maximum(force.tyre, 0.0)
                                                           / LOOP_ONSET)) * loop),
    }


def _fit(target: np.ndarray, columns: list[np.ndarray]) -> tuple[np.ndarray, list[float]]:
    """Least-squares coefficients and each column's partial R²: the share of what the other
    columns leave unexplained that the column explains, 1 − SSE(all)/SSE(all but it)."""
    matrix = np.column_stack(columns)
    scale = np.linalg.norm(matrix, axis=0)
    scale[scale == 0] = 1.0
    coefficients, *_ = np.linalg.lstsq(matrix / scale, target, rcond=None)
    full = float(np.sum((target - (matrix / scale) @ coefficients) ** 2))
    shares = []
    for index in range(matrix.shape[1]):
        rest = np.delete(matrix / scale, index, axis=1)
        reduced, *_ = np.linalg.lstsq(rest, target, rcond=None)
        dropped = float(np.sum((target - rest @ reduced) ** 2))
        shares.append(max(dropped - full, 0.0) / dropped if dropped > 0 else 0.0)
    return coefficients / scale, shares


def signatures(forces: list[MissingForce]) -> list[Signature]:
    """The shapes fitted to the missing strut and tyre forces, pooled over ``forces``."""
    forces = [f for f in forces if f is not None and f.time.size > 10]
    if not forces:
        return []
    shapes = [_shapes(f) for f in forces]
    names = list(shapes[0])
    out = []
    for side, target in (("strut", np.concatenate([f.strut_missing for f in forces])),
                         ("tyre", np.concatenate([f.tyre_missing for f in forces]))):
        chosen = [n for n in names if shapes[0][n][0] == side]
        columns = [np.concatenate([s[n][3] for s in shapes]) for n in chosen]
        coefficients, shares = _fit(target, columns)
        for name, coefficient, share in zip(chosen, coefficients, shares):
            _, effect, unit, _ = shapes[0][name]
            out.append(Signature(side, name, effect, float(coefficient), unit, float(share)))
    return out


def pointed_effects(found: list[Signature]) -> dict[str, float]:
    """Effect -> the largest share among its seen shapes (the effects the missing force
    points to)."""
    out: dict[str, float] = {}
    for signature in found:
        if signature.seen:
            out[signature.effect] = max(out.get(signature.effect, 0.0), signature.share)
    return out



def campaign_missing_forces(campaign, gear_id: str, run_ids, configure) -> list[MissingForce]:
    """:func:`missing_force` of ``gear_id`` in each of ``run_ids`` that records load, stroke
    and tyre deflection, under ``configure(nominal model)`` (the calibration's)."""
    runs = {run.id: run for run in campaign.spec.runs}
    weight = campaign.gear_units[gear_id].static_weight.si
    out = []
    for run_id in run_ids:
        gear = campaign.series[run_id].gears[gear_id]
        if gear.stroke is None or gear.tyre is None:
            continue
        model = configure(drop_model_for(campaign.spec, runs[run_id], gear_id,
                                         campaign.spec_path.name, campaign.lines, []))
        found = missing_force(run_id, campaign.series[run_id].time, gear.load, gear.stroke,
                              gear.tyre, model, weight)
        if found is not None:
            out.append(found)
    return out
