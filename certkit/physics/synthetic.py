"""Synthetic campaigns: simulated runs written in the campaign's own data format.

``simulate_campaign`` simulates every run of a campaign with the drop model of each gear
unit, adds realistic sensor effects (Gaussian noise, quantisation, zero offsets), and
writes the data files and a campaign file pointing at them.  The offsets are recorded in
each column's ``offset`` so that zeroing the channels is explicit in the spec.  Seeds are
fixed: the same inputs give the same bytes.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from certkit.compliance.clauses import ideal_impact_velocity
from certkit.errors import CertkitInputError
from certkit.outputs import staged_folder
from certkit.physics.drop_model import DropModel
from certkit.physics.effects import SensorDynamics
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import simulate_reference
from certkit.spec.campaign import Campaign
from certkit.spec.yamlsource import load_yaml


@dataclass(frozen=True)
class SensorModel:
    """Sensor effects added to simulated channels (SI: N, m, m/s²)."""

    load_noise: float = 20.0
    load_step: float = 1.0
    load_offset: float = 10.0          # offsets drawn uniformly in ±this
    travel_noise: float = 5.0e-5
    travel_step: float = 1.0e-5
    travel_offset: float = 2.0e-4
    acceleration_noise: float = 0.05
    acceleration_step: float = 0.01
    displacement_noise: float = 5.0e-5
    displacement_step: float = 1.0e-5


    #: Error of the zero offsets written into the spec (uniform in ±this): the offsets a
    #: test engineer reads before a drop are themselves measured, so zeroing is imperfect.
    load_zero_error: float = 0.0
    travel_zero_error: float = 0.0


NO_SENSOR_EFFECTS = SensorModel(0, 0, 0, 0, 0, 0, 0, 0, 0, 0)


def _measured(values: np.ndarray, noise: float, step: float, offset: float, rng) -> tuple:
    """Add an offset, noise and quantisation; returns (readings, the offset applied)."""
    bias = float(rng.uniform(-offset, offset)) if offset else 0.0
    if step:
        bias = round(bias / step) * step
    readings = values + bias + (rng.normal(0.0, noise, values.shape) if noise else 0.0)
    if step:
        readings = np.round(readings / step) * step
    return readings, bias


def _decimals(step: float) -> int:
    return max(0, -int(math.floor(math.log10(step)))) if step else 9


@dataclass(frozen=True)
class Histories:
    """One gear unit's noise-free channels in one drop, as a simulator gives them (SI):
    what :func:`write_campaign` records.  ``acceleration`` is the drop mass's, positive
    upward; ``displacement`` its travel from contact, positive downward; ``weight`` the
    share of the drop mass the unit carries (to average the drop mass's channels)."""

    time: np.ndarray
    load: np.ndarray
    stroke: np.ndarray
    tyre: np.ndarray
    acceleration: np.ndarray
    displacement: np.ndarray
    weight: float


def simulate_campaign(campaign: Campaign, out_dir: str | Path, seed: int = 0,
                      sensors: SensorModel = SensorModel(), duration: float = 2.0,
                      lead: float = 0.1, effects: list[str] | None = None,
                      truth: Callable[[str, DropModel], DropModel] | None = None,
                      recorder: SensorDynamics | None = None, note: str | None = None) -> Path:
    """Simulate every run of ``campaign`` and write a synthetic campaign into ``out_dir``.

    Writes ``out_dir/campaign.yaml`` (the original spec with each run's ``data`` pointing at
    the simulated file) and ``out_dir/data/<run>.csv``.  Returns the new spec's path.

    ``truth(gear_id, model)`` turns the spec's model of a gear unit (with ``effects``) into
    the one simulated; ``recorder`` replaces the spec's sensor dynamics; ``note`` replaces
    the assumption the spec gains (which otherwise names the effects simulated).
    """
    spec = campaign.spec
    rate = spec.instrumentation.sampling_rate.si if spec.instrumentation else 1000.0

    def histories(index: int, run) -> dict[str, Histories]:
        velocity = ideal_impact_velocity(run.drop_height.si)
        models = {gear_id: drop_model_for(spec, run, gear_id, str(campaign.spec_path.name),
                                          campaign.lines, effects)
                  for gear_id in run.gear_units}
        if truth is not None:
            models = {gear_id: truth(gear_id, model) for gear_id, model in models.items()}
        out = {}
        for gear_id, model in models.items():
            drop = simulate_reference(model, velocity, duration, rate, lead, run=run.id)
            record = (_recorder(campaign, effects, drop.time) if recorder is None
                      else lambda signal, sensor=recorder, t=drop.time: sensor.apply(t, signal))
            out[gear_id] = Histories(drop.time, record(drop.load), record(drop.stroke),
                                     record(drop.tyre), record(drop.acceleration),
                                     record(drop.displacement), model.upper_mass)
        return out

    note = note or (f"Synthetic time histories simulated by certkit (drop model of each gear "
                    f"unit, effects: "
                    f"{', '.join(effects if effects is not None else spec.model.effects) or 'none'}"
                    f"; seed {seed}); sensor noise, quantisation and zero offsets added.")
    return write_campaign(campaign, out_dir, histories, note, seed, sensors, rate)


def write_campaign(campaign: Campaign, out_dir: str | Path,
                   histories: Callable[[int, object], dict[str, Histories]], note: str,
                   seed: int = 0, sensors: SensorModel = SensorModel(),
                   rate: float | None = None) -> Path:
    """Write a campaign whose runs hold the channels ``histories(index, run)`` gives
    (gear unit -> :class:`Histories`, as recorded but noise-free) with ``sensors``' noise,
    quantisation and zero offsets added, into ``out_dir``: the spec (``note`` added to its
    assumptions and at its top) and ``data/<run>.csv``.  Returns the new spec's path.  Any
    simulator can fill a campaign this way (the blind check's independent truths do)."""
    spec = campaign.spec
    if rate is None:
        rate = spec.instrumentation.sampling_rate.si if spec.instrumentation else 1000.0
    raw, _ = load_yaml(campaign.spec_path, str(campaign.spec_path))  # read as it was loaded
    # the new campaign has no blind-check record of its own (the files are not copied)
    for key in ("blind_check", "sealed_blind_check"):
        (raw.get("model") or {}).get("gap", {}).pop(key, None)
    files = {"campaign.yaml"} | {f"data/{run.id}.csv" for run in spec.runs}
    inputs = [item.path for item in campaign.inputs]
    with staged_folder(out_dir, inputs, files) as staging:
        (staging / "data").mkdir()
        for index, run in enumerate(spec.runs):
            rng = np.random.default_rng([seed, index])
            drops = histories(index, run)
            time = next(iter(drops.values())).time
            columns = {"t_s": (time, 1.0, 6)}
            mapping = {}
            for gear_id, drop in drops.items():
                load, load_bias = _measured(drop.load, sensors.load_noise,
                                            sensors.load_step, sensors.load_offset, rng)
                stroke, stroke_bias = _measured(drop.stroke, sensors.travel_noise,
                                                sensors.travel_step, sensors.travel_offset, rng)
                tyre, tyre_bias = _measured(drop.tyre, sensors.travel_noise,
                                            sensors.travel_step, sensors.travel_offset, rng)
                if sensors.load_zero_error or sensors.travel_zero_error:
                    load_bias += rng.uniform(-1, 1) * sensors.load_zero_error
                    stroke_bias += rng.uniform(-1, 1) * sensors.travel_zero_error
                    tyre_bias += rng.uniform(-1, 1) * sensors.travel_zero_error
                columns[f"{gear_id}_load_N"] = (load, 1.0, _decimals(sensors.load_step))
                columns[f"{gear_id}_stroke_mm"] = (stroke, 1e3, _decimals(sensors.travel_step * 1e3))
                columns[f"{gear_id}_tyre_mm"] = (tyre, 1e3, _decimals(sensors.travel_step * 1e3))
                mapping[gear_id] = {
                    "vertical_load": {"column": f"{gear_id}_load_N", "unit": "N",
                                      "offset": round(load_bias, 9)},
                    "strut_stroke": {"column": f"{gear_id}_stroke_mm", "unit": "mm",
                                     "offset": round(stroke_bias * 1e3, 9)},
                    "tyre_deflection": {"column": f"{gear_id}_tyre_mm", "unit": "mm",
                                        "offset": round(tyre_bias * 1e3, 9)}}
            # the drop mass: each unit's upper mass moves as the airframe; weighted by upper mass
            total = sum(d.weight for d in drops.values())
            acceleration = sum(d.weight * d.acceleration for d in drops.values()) / total
            displacement = sum(d.weight * d.displacement for d in drops.values()) / total
            acceleration, _ = _measured(acceleration, sensors.acceleration_noise,
                                        sensors.acceleration_step, 0.0, rng)
            displacement, _ = _measured(displacement, sensors.displacement_noise,
                                        sensors.displacement_step, 0.0, rng)
            columns["acc_ms2"] = (acceleration, 1.0, _decimals(sensors.acceleration_step))
            columns["x_mm"] = (displacement, 1e3, _decimals(sensors.displacement_step * 1e3))
            _write_csv(staging / "data" / f"{run.id}.csv", columns)
            raw["runs"][index]["data"] = {
                "file": f"data/{run.id}.csv", "origin": "synthetic",
                "time": {"column": "t_s", "unit": "s"},
                "sampling_rate": f"{rate:g} Hz", "gears": mapping,
                "drop_mass_acceleration": {"column": "acc_ms2", "unit": "m/s^2",
                                           "reference": "kinematic"},
                "drop_mass_displacement": {"column": "x_mm", "unit": "mm"}}
        raw.setdefault("assumptions", []).append(note)
        text = yaml.safe_dump(raw, sort_keys=False, allow_unicode=True, width=100)
        (staging / "campaign.yaml").write_text("# " + note + "\n" + text, encoding="utf-8")
    return Path(out_dir) / "campaign.yaml"


def _recorder(campaign: Campaign, effects, time):
    """The logger's view of a channel: sensor dynamics when that effect is on, else as is."""
    spec = campaign.spec
    chosen = spec.model.effects if effects is None else effects
    if "sensor-dynamics" not in chosen:
        return lambda signal: signal
    if spec.model.sensor is None:
        raise CertkitInputError.single(campaign.spec_path.name, campaign.line("model"),
                                       "model.sensor", "needed for the effect 'sensor-dynamics' "
                                       "(cutoff, order, delay)")
    sensor = SensorDynamics(spec.model.sensor.cutoff.si, spec.model.sensor.order,
                            spec.model.sensor.delay.si)
    return lambda signal: sensor.apply(time, signal)


def _write_csv(path: Path, columns: dict) -> None:
    names = list(columns)
    scaled = [values * factor for values, factor, _ in columns.values()]
    formats = [f"{{:.{decimals}f}}" for _, _, decimals in columns.values()]
    with path.open("w", encoding="utf-8", newline="\n") as handle:
        handle.write(",".join(names) + "\n")
        for row in zip(*scaled):
            handle.write(",".join(fmt.format(value) for fmt, value in zip(formats, row)) + "\n")


# --------------------------------------------------------------------------- example campaigns
def _merge(target: dict, changes: dict) -> None:
    for key, value in changes.items():
        if isinstance(value, dict) and isinstance(target.get(key), dict):
            _merge(target[key], value)
        else:
            target[key] = value


def truth_spec(spec: Path, folder: Path, changes: dict[str, dict], effects: list[str]) -> Path:
    """A campaign's spec as the "truth" a synthetic campaign is simulated from.

    ``changes`` maps a gear unit id to the spec keys in which the simulated gear differs
    from the spec's (merged into that gear unit, as a real gear differs from its drawing);
    every run's ``data`` block is dropped and ``model.effects`` set to ``effects``.  Written
    as ``folder/truth.yaml``; returns its path.
    """
    raw, _ = load_yaml(Path(spec), str(spec))
    for unit in raw["gear_units"]:
        _merge(unit, changes.get(unit["id"], {}))
    for run in raw["runs"]:
        run.pop("data", None)
    raw["model"] = {"effects": list(effects)}
    path = Path(folder) / "truth.yaml"
    path.write_text(yaml.safe_dump(raw, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return path


def check_requested(description: str) -> bool:
    """The command line of an example's synthesise.py: True for ``--check``."""
    parser = argparse.ArgumentParser(description=description.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="compare with the committed files instead of writing them")
    return parser.parse_args().check


def write_or_check(fresh: list[Path], folder: Path, check: bool) -> int:
    """Copy freshly simulated data files into ``folder`` or, with ``check``, only compare
    them with the files there; returns the exit status (1: a file differs)."""
    folder = Path(folder)
    differ = [f.name for f in fresh if not (folder / f.name).exists()
              or (folder / f.name).read_bytes() != f.read_bytes()]
    if check:
        if differ:
            print("differ from a fresh simulation: " + ", ".join(differ))
            return 1
        print(f"{len(fresh)} data files match a fresh simulation")
        return 0
    folder.mkdir(exist_ok=True)
    for f in fresh:
        (folder / f.name).write_bytes(f.read_bytes())
    print(f"wrote {len(fresh)} files into {folder}")
    return 0
