"""Synthetic campaigns: simulated runs in the campaign's own format, read back by the
same code that reads measured runs."""

import hashlib
import math

import numpy as np

import pytest
from typer.testing import CliRunner

from certkit import assess, load_campaign
from certkit.cli import app
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import simulate_reference
from certkit.physics.synthetic import NO_SENSOR_EFFECTS, simulate_campaign

G = 9.80665
runner = CliRunner()


def truth(spec_path, run_index):
    campaign = load_campaign(spec_path)
    run = campaign.spec.runs[run_index]
    model = drop_model_for(campaign.spec, run, "left-main")
    return simulate_reference(model, math.sqrt(2 * G * run.drop_height.si))


def test_model_from_the_spec_is_the_seed_gear(physics_campaign):
    drop = truth(physics_campaign, 2)
    # the independently written simulator gave 1530 kgf, 98.5 mm, 46.3 mm at 300 mm
    assert drop.load.max() / G == pytest.approx(1530, abs=1.5)
    assert drop.stroke.max() * 1000 == pytest.approx(98.5, abs=0.15)
    assert drop.tyre.max() * 1000 == pytest.approx(46.3, abs=0.1)


@pytest.mark.parametrize("noisy", [False, True])
def test_synthetic_runs_give_back_the_simulators_energies(physics_campaign, tmp_path, noisy):
    out = tmp_path / "synthetic"
    kwargs = {} if noisy else {"sensors": NO_SENSOR_EFFECTS}
    spec = simulate_campaign(load_campaign(physics_campaign), out, seed=1, **kwargs)
    # synthetic files are never compliance evidence; to check the foundation's energy
    # integrals on them, declare them measured (as a lab's logger file would be)
    text = spec.read_text(encoding="utf-8")
    assert text.count("origin: synthetic") == 3
    spec.write_text(text.replace("origin: synthetic", "origin: measured"), encoding="utf-8")
    assessment = assess(load_campaign(spec))
    for index, run in enumerate(assessment.runs):
        gear = run.gears[0]
        strut, tyre = truth(physics_campaign, index).absorbed_on_loading()
        assert gear.get("E_s") == pytest.approx(strut, rel=0.005)
        assert gear.get("E_t") == pytest.approx(tyre, rel=0.005)
    assert assessment.runs[0].series is not None
    assert any("Synthetic time histories" in a for a in assessment.campaign.spec.assumptions)


def test_synthetic_runs_are_not_compliance_evidence(physics_campaign, tmp_path):
    spec = simulate_campaign(load_campaign(physics_campaign), tmp_path / "synthetic", seed=1)
    assessment = assess(load_campaign(spec))
    assert all(run.series is None for run in assessment.runs)
    assert all(gear.get("F_peak") is None for run in assessment.runs for gear in run.gears)
    flagged = [f for f in assessment.findings if f.check == "synthetic-data"]
    assert [f.run for f in flagged] == ["D200", "D250", "D300"]
    assert assessment.outcome == "COMPLIANCE NOT SHOWN"


def test_same_seed_same_bytes_other_seed_other_noise(physics_campaign, tmp_path):
    campaign = load_campaign(physics_campaign)

    def digest(folder):
        return hashlib.sha256((folder / "data" / "D300.csv").read_bytes()).hexdigest()

    simulate_campaign(campaign, tmp_path / "a", seed=3)
    simulate_campaign(campaign, tmp_path / "b", seed=3)
    simulate_campaign(campaign, tmp_path / "c", seed=4)
    assert digest(tmp_path / "a") == digest(tmp_path / "b") != digest(tmp_path / "c")
    assert (tmp_path / "a" / "campaign.yaml").read_bytes() == (
        tmp_path / "b" / "campaign.yaml").read_bytes()


def test_simulate_command_names_a_missing_parameter(physics_campaign, tmp_path):
    text = physics_campaign.read_text(encoding="utf-8").replace(
        "      gas_volume: 650.3096792 cm^3\n", "")
    physics_campaign.write_text(text, encoding="utf-8")
    result = runner.invoke(app, ["simulate", str(physics_campaign), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2
    assert "gear_units[0].strut.gas_volume: needed to simulate" in result.output
    assert not (tmp_path / "o").exists()


def test_gas_volume_below_the_swept_volume_is_an_input_error(physics_campaign, tmp_path):
    # A_a * s_max = 2827.43 mm^2 * 200 mm = 565.49 cm^3 > 0.98 * 500 cm^3
    text = physics_campaign.read_text(encoding="utf-8").replace(
        "gas_volume: 650.3096792 cm^3", "gas_volume: 500 cm^3")
    physics_campaign.write_text(text, encoding="utf-8")
    result = runner.invoke(app, ["simulate", str(physics_campaign), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2 and "565.487 cm^3" in result.output


def test_a_gas_spring_that_cannot_carry_the_weight_is_an_input_error(physics_campaign, tmp_path):
    # 0.01 MPa gauge = 0.1113 MPa absolute; p_static = p_atm + 283.5 kg * g / A_a = 1.0846 MPa;
    # volume ratio (1.0846/0.1113)^(1/1.2) = 6.68, so s = 230 mm * (1 - 1/6.68) = 195.6 mm,
    # beyond a 150 mm design stroke
    text = physics_campaign.read_text(encoding="utf-8").replace(
        "gas_precharge_pressure: 0.8 MPa", "gas_precharge_pressure: 0.01 MPa").replace(
        "design_stroke: 200 mm", "design_stroke: 150 mm")
    physics_campaign.write_text(text, encoding="utf-8")
    result = runner.invoke(app, ["simulate", str(physics_campaign), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2 and "cannot hold the static load" in result.output


def test_every_effect_can_be_switched_on_from_the_spec(physics_campaign, tmp_path):
    text = physics_campaign.read_text(encoding="utf-8")
    text = text.replace("      damping: 0.05 s/m\n", "      damping: 0.05 s/m\n      hysteresis: 5 %\n")
    text = text.replace("      seal_friction: {constant: 80 N, pressure_factor: 0.03}\n",
                        "      seal_friction: {constant: 80 N, pressure_factor: 0.03}\n"
                        # 69.4 mm^2 = pi*9.4^2/4, the nominal orifice; closing to 50 mm^2
                        "      metering_pin: {strokes: [0 mm, 100 mm, 200 mm], "
                        "areas: [69.4 mm^2, 55 mm^2, 50 mm^2]}\n"
                        "      heat_transfer: {time_constant: 1 s}\n"
                        "      oil: {bulk_modulus: 1.5 GPa, volume: 300 cm^3}\n"
                        "    leg: {axle_mass: 5 kg, stiffness: 3000 N/mm, damping: 300 N*s/m}\n")
    text = text.replace("  effects: [rebound-orifice, seal-friction]",
                        "  effects: [rebound-orifice, seal-friction, metering-pin, tyre-hysteresis,"
                        " heat-transfer, oil-compressibility, leg-flexibility, platform-compliance,"
                        " sensor-dynamics]\n  sensor: {cutoff: 100 Hz, order: 2, delay: 2 ms}")
    text = text.replace("  sampling_rate: 1000 Hz\n", "  sampling_rate: 1000 Hz\n"
                        "  platform: {mass: 50 kg, stiffness: 5e4 N/mm, damping: 5000 N*s/m}\n")
    physics_campaign.write_text(text, encoding="utf-8")
    campaign = load_campaign(physics_campaign)
    model = drop_model_for(campaign.spec, campaign.spec.runs[2], "left-main")
    # every effect switched on, in the order of the effect registry (their terms are
    # independent, so the order is a convention)
    assert [t.name for t in model.terms()][4:] == [
        "seal friction", "rebound orifice", "metering pin", "tyre hysteresis", "heat transfer",
        "oil compressibility", "leg flexibility", "platform compliance"]
    assert model.effect("leg flexibility").stiffness == pytest.approx(3.0e6)
    assert model.effect("platform compliance").stiffness == pytest.approx(5.0e7)
    # k_oil = β·A_h²/V_oil = 1.5e9 · (2.827433e-3)² / 3e-4
    assert model.effect("oil compressibility").stiffness == pytest.approx(3.997e7, rel=1e-3)
    spec = simulate_campaign(campaign, tmp_path / "all", sensors=NO_SENSOR_EFFECTS)
    recorded = load_campaign(spec).series["D300"].gears["left-main"].load
    reference = simulate_reference(model, math.sqrt(2 * G * 0.3))
    # the recorded peak is the low-passed one: lower than the simulated peak, not higher
    assert recorded.max() < reference.load.max()


def test_sensor_dynamics_needs_its_parameters(physics_campaign, tmp_path):
    text = physics_campaign.read_text(encoding="utf-8").replace(
        "  effects: [rebound-orifice, seal-friction]",
        "  effects: [rebound-orifice, seal-friction, sensor-dynamics]")
    physics_campaign.write_text(text, encoding="utf-8")
    result = runner.invoke(app, ["simulate", str(physics_campaign), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2 and "model.sensor" in result.output
    assert not (tmp_path / "o").exists()


def test_a_failed_integration_names_the_run_and_time_and_writes_nothing(physics_campaign, tmp_path,
                                                                       monkeypatch):
    import certkit.physics.simulation as simulation

    class Failed:
        success, t, message = False, np.array([0.0, 0.0123]), "step size too small"

    monkeypatch.setattr(simulation, "solve_ivp", lambda *args, **kwargs: Failed())
    result = runner.invoke(app, ["simulate", str(physics_campaign), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2
    assert "run D200: the integrator failed at t = 0.0123 s after contact" in result.output
    assert not (tmp_path / "o").exists() and sorted(p.name for p in tmp_path.iterdir()) == ["physics"]
