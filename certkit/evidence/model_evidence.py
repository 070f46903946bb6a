"""The physics-model evidence of a report: the calibration of every gear unit whose drop
model the spec allows, its identification and its sim-to-real gap diagnosis, or plainly why
there is none.

Above :mod:`certkit.physics.calibration`, :mod:`certkit.ident.protocol` and :mod:`certkit.gap.diagnosis`,
which it runs; the report only lays out what it returns.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from threadpoolctl import threadpool_limits

from certkit.errors import CertkitInputError
from certkit.gap.diagnosis import gap_diagnosis
from certkit.ident.protocol import identify
from certkit.physics.calibration import Calibration, calibrate
from certkit.physics.fitting import FitError
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import SimulationError
from certkit.spec.campaign import Campaign


@dataclass(frozen=True)
class ModelEvidence:
    """What the report's governing-equation section shows: a calibration, or why none."""

    calibration: Calibration | None
    note: str
    synthetic_runs: tuple[str, ...] = ()
    identification: object | None = None   # certkit.ident.protocol.Identification
    gap: dict = field(default_factory=dict)  # gear id -> certkit.gap.diagnosis.GapDiagnosis
    gap_notes: tuple[str, ...] = ()          # gear units not diagnosed, and why, in words


def model_evidence(campaign: Campaign, identification: bool = True,
                   gap: bool = True, progress=None) -> ModelEvidence:
    """Calibrate every recorded gear unit that the spec gives the model's parameters for,
    identify its block-oriented models (``identification``) and diagnose its sim-to-real
    gap (``gap``); otherwise say plainly why a section is empty.  ``progress(message)`` is
    told each step as it starts."""
    progress = progress or (lambda message: None)
    spec = campaign.spec
    synthetic = tuple(r.id for r in spec.runs if r.data is not None and r.data.origin == "synthetic")
    recorded = [g.id for g in spec.gear_units
                if any(s is not None and g.id in s.gears for s in campaign.series.values())]
    if not recorded:
        return ModelEvidence(None, "No run has time histories, so the drop model cannot be "
                                   "compared with or calibrated against the tests.", synthetic)
    ready, missing = [], []
    for gear_id in recorded:
        run = next(r for r in spec.runs if gear_id in r.gear_units)
        try:
            drop_model_for(spec, run, gear_id, campaign.spec_path.name, campaign.lines)
            ready.append(gear_id)
        except CertkitInputError as error:
            missing += [f"{p.key} ({p.message})" for p in error.problems]
    if not ready:
        return ModelEvidence(None, "The drop model cannot be built from the spec: "
                                   + "; ".join(missing) + ".", synthetic)
    note = "" if not missing else ("Not modelled (the drop model cannot be built from the "
                                   "spec): " + "; ".join(missing) + ".")
    units = ", ".join(ready)
    with threadpool_limits(limits=1):   # results independent of the machine's core count
        progress(f"calibrating the drop model of {units}")
        calibration = calibrate(campaign, gears=ready)
        diagnoses, notes = _gap(campaign, ready, progress) if gap else ({}, ())
    if identification:
        progress(f"identifying Hammerstein, Wiener and NARX models of {units}")
    return ModelEvidence(calibration, note, synthetic,
                         identify(campaign, gears=ready) if identification else None,
                         diagnoses, notes)


def _gap(campaign: Campaign, gears: list[str], progress) -> tuple[dict, tuple[str, ...]]:
    """The gap diagnosis of each gear unit; a unit whose drops allow none (one drop height,
    no training or held-out run left) gets a note saying why instead."""

    diagnoses, notes = {}, []
    for gear_id in gears:
        progress(f"diagnosing the sim-to-real gap of {gear_id}")
        try:
            diagnoses[gear_id] = gap_diagnosis(campaign, gear_id)
        except CertkitInputError as error:
            notes.append(f"{gear_id}: not diagnosed. " + " ".join(
                p.message[:1].upper() + p.message[1:] for p in error.problems))
        except (FitError, SimulationError) as error:
            # one gear's failed refit must not take the compliance report down with it
            notes.append(f"{gear_id}: not diagnosed: the diagnosis failed ({error}).")
    return diagnoses, tuple(notes)
