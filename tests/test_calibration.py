"""Calibration: fitted parameters recover a known truth from synthetic noisy runs; the
command line reports estimates, uncertainty and identifiability."""

import json

import pytest
from typer.testing import CliRunner

from certkit import load_campaign
from certkit.physics.calibration import calibrate
from certkit.cli import app
from certkit.physics.synthetic import SensorModel, simulate_campaign

from .conftest import PHYSICS_SPEC, write_campaign

runner = CliRunner()

# the truth differs from the spec's nominal values by 5-25 %
TRUTH = {"discharge_coefficient: 0.6": "discharge_coefficient: 0.65",
         "gas_precharge_pressure: 0.8 MPa": "gas_precharge_pressure: 0.85 MPa",
         "reference_load: 12471.77 N": "reference_load: 13500 N",
         "constant: 80 N": "constant: 100 N"}
TRUE_VALUES = {"discharge-coefficient": 0.65, "gas-precharge": 0.85e6 + 101325.0,
               "tyre-stiffness": 13500.0, "friction": 100.0, "polytropic-exponent": 1.2,
               "tyre-exponent": 1.26,
               # the rigid stop's give under the preload: A·p_gauge / 2e7 N/m
               "top-out-compression": 2827.433388e-6 * 0.85e6 / 2.0e7}
NOISE = SensorModel()  # 20 N load noise, 0.05 mm travel noise


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """A synthetic campaign simulated with the truth, whose spec states the nominal values."""
    root = tmp_path_factory.mktemp("calibration")
    truth_text = PHYSICS_SPEC
    for nominal, true in TRUTH.items():
        assert nominal in truth_text
        truth_text = truth_text.replace(nominal, true)
    truth = write_campaign(root / "truth", truth_text)
    written = simulate_campaign(load_campaign(truth), root / "measured", seed=7, sensors=NOISE)
    text = written.read_text(encoding="utf-8")
    for nominal, true in TRUTH.items():  # the engineer's spec: nominal values
        text = text.replace(true, nominal)
    written.write_text(text, encoding="utf-8")
    return written


@pytest.fixture(scope="module")
def result(measured):
    return calibrate(load_campaign(measured))


def test_calibration_recovers_the_truth_within_its_standard_errors(result):
    gear = result.gears[0]
    # fitted to the training drops; the highest drop is held out and only simulated
    assert gear.runs == ("D200", "D250") and gear.held_out == ("D300",)
    assert {(e.run, e.role) for e in gear.errors} == {("D200", "training"),
                                                      ("D250", "training"),
                                                      ("D300", "held out")}
    for parameter, estimate, error in zip(gear.fit.parameters, gear.fit.estimate,
                                          gear.fit.standard_error):
        true = TRUE_VALUES[parameter.name]
        if parameter.name == "top-out-compression":
            # the truth's stop is rigid (its penalty give, 0.12 mm, is no compliance):
            # seen only through the stroke before the strut breaks out, the fitted stop is
            # as stiff as that to within the travel noise (0.05 mm)
            assert estimate <= true + NOISE.travel_noise, (estimate, true)
            continue
        assert abs(estimate - true) <= max(4 * error, 1e-3 * true), parameter.name
        assert estimate == pytest.approx(true, rel=0.02), parameter.name


def test_calibrated_model_fits_to_the_noise_and_the_nominal_does_not(result):
    # the held-out drop too: the calibrated model predicts it to within the noise
    for error in result.gears[0].errors:
        noise = 20.0 if error.channel == "load" else 5.0e-5
        assert error.calibrated == pytest.approx(noise, rel=0.1)   # white noise RMS
        assert error.nominal > 5 * noise


def test_cli_prints_estimates_correlations_and_writes_json(measured, tmp_path):
    target = tmp_path / "calibration.json"
    outcome = runner.invoke(app, ["calibrate", str(measured), "-p", "discharge-coefficient",
                                  "-p", "tyre-stiffness", "--json", str(target)])
    assert outcome.exit_code == 0, outcome.output
    assert "discharge-coefficient" in outcome.output and "correlation" in outcome.output
    document = json.loads(target.read_text(encoding="utf-8"))
    names = [p["name"] for p in document["gear_units"][0]["parameters"]]
    assert names == ["discharge-coefficient", "tyre-stiffness"]
    assert len(document["gear_units"][0]["rmse"]) == 9  # 3 runs x 3 channels, D300 held out
    assert {r["role"] for r in document["gear_units"][0]["rmse"] if r["run"] == "D300"} == \
        {"held out"}


def test_a_parameter_ending_on_its_bound_is_flagged(measured):
    # the truth has C_d = 0.65: bounds that stop it at 0.62 leave it on the bound
    from certkit.physics.calibration import KNOBS, Knob

    campaign = load_campaign(measured)
    narrow = Knob(**{**KNOBS["discharge-coefficient"].__dict__,
                     "name": "narrow-cd", "bounds": lambda nominal: (0.55, 0.62)})
    KNOBS["narrow-cd"] = narrow
    try:
        gear = calibrate(campaign, knobs=["narrow-cd", "tyre-stiffness"]).gears[0]
    finally:
        del KNOBS["narrow-cd"]
    assert gear.fit.estimate[0] == pytest.approx(0.62)
    assert any("upper bound" in w and "narrow-cd" in w for w in gear.fit.warnings)


def test_unknown_parameter_and_missing_effect_are_input_errors(measured, physics_campaign):
    outcome = runner.invoke(app, ["calibrate", str(measured), "-p", "orifice-size"])
    assert outcome.exit_code == 2
    assert "model.calibration.parameters" in outcome.output and "orifice-size" in outcome.output
    # a campaign without time histories has nothing to calibrate against
    outcome = runner.invoke(app, ["calibrate", str(physics_campaign)])
    assert outcome.exit_code == 2 and "nothing to fit" in outcome.output


def test_a_fit_that_meets_non_finite_residuals_is_reported_not_a_traceback(measured,
                                                                           monkeypatch):
    import certkit.physics.calibration
    from certkit.physics.fitting import FitError

    def failing(*args, **kwargs):
        raise FitError("4 of 9 residuals are not finite at gas-precharge = 1.2e5 Pa")

    monkeypatch.setattr(certkit.physics.calibration, "calibrate", failing)
    outcome = runner.invoke(app, ["calibrate", str(measured)])
    assert outcome.exit_code == 2
    assert "residuals are not finite at gas-precharge" in outcome.output
    assert "Traceback" not in outcome.output


def test_further_starts_are_recorded_and_one_basin_keeps_the_first_fit(measured, tmp_path):
    """Two knobs whose truth lies 8 % from the nominal: every start reaches the first fit's
    minimum, so the first fit is kept exactly and the starts are recorded, inside the
    bounds."""
    target = tmp_path / "starts.json"
    knobs = ["discharge-coefficient", "tyre-stiffness"]
    outcome = runner.invoke(app, ["calibrate", str(measured), "-p", knobs[0], "-p", knobs[1],
                                  "--starts", "2", "--json", str(target)])
    assert outcome.exit_code == 0, outcome.output
    assert "from 2 further starts" in " ".join(outcome.output.split())
    gear = json.loads(target.read_text(encoding="utf-8"))["gear_units"][0]
    starts = gear["further_starts"]
    assert starts["kept_start"] is None and starts["failures"] == []
    assert len(starts["points"]) == len(starts["training_costs"]) == 2
    for point in starts["points"]:
        for value, parameter in zip(point, gear["parameters"]):
            assert parameter["lower"] < value < parameter["upper"]
    plain = calibrate(load_campaign(measured), knobs=knobs).gears[0]
    assert plain.search is None
    assert [p["estimate"] for p in gear["parameters"]] == [float(e) for e in plain.fit.estimate]
    assert [p["nominal"] for p in gear["parameters"]] == [p.nominal for p in plain.fit.parameters]


def test_the_spec_sets_the_further_starts_and_the_option_is_checked(measured):
    from certkit.physics.calibration import calibration_starts

    text = measured.read_text(encoding="utf-8")
    assert "\nmodel:\n  effects:" in text
    spec = measured.parent / "with-starts.yaml"     # beside the data files it names
    spec.write_text(text.replace("\nmodel:\n  effects:",
                                 "\nmodel:\n  calibration: {starts: 1}\n  effects:"),
                    encoding="utf-8")
    campaign = load_campaign(spec)
    assert calibration_starts(campaign) == 1 and calibration_starts(load_campaign(measured)) == 0
    gear = calibrate(campaign, knobs=["discharge-coefficient"]).gears[0]
    assert len(gear.search.points) == 1
    outcome = runner.invoke(app, ["calibrate", str(measured), "--starts", "21"])
    assert outcome.exit_code == 2
    assert "--starts: expected a whole number from 0 to 20, found 21" in outcome.output
    # a YAML true, a quoted number or a float is not read as a count of starts
    for value, found in (("true", "got True"), ('"3"', 'got "3"'), ("2.0", "got 2.0")):
        spec.write_text(text.replace("\nmodel:\n  effects:",
                                     f"\nmodel:\n  calibration: {{starts: {value}}}\n  effects:"),
                        encoding="utf-8")
        outcome = runner.invoke(app, ["validate", str(spec)])
        assert outcome.exit_code == 2, (value, outcome.output)
        message = " ".join(outcome.output.split())
        line = text[:text.index("\nmodel:\n  effects:")].count("\n") + 3   # the key's line
        assert f"{spec.name}:{line} model.calibration.starts: input should be a valid " \
            f"integer; {found}" in message


def test_the_report_states_the_specs_further_starts(measured):
    """The spec's model.calibration.starts reaches appendix A's method text through the
    model evidence (one home for the setting: the evidence carries what was used)."""
    import html as markup

    from certkit import assess
    from certkit.evidence import report as report_module
    from certkit.evidence.model_evidence import ModelEvidence
    from certkit.evidence.provenance import provenance
    from certkit.physics.calibration import Calibration

    campaign = load_campaign(measured)
    for starts, words in ((3, "The fit starts from the spec's values and from 3 further "
                              "starts (model.calibration.starts) spread over the parameters' "
                              "bounds"),
                          (0, "The fit starts from the spec's values only "
                              "(model.calibration.starts is 0)")):
        evidence = ModelEvidence(Calibration((), ()), "", calibration_starts=starts)
        page = report_module.render_html(report_module.build_view(
            assess(campaign), provenance(campaign.inputs), evidence))
        section = " ".join(markup.unescape(page[page.index('<section id="model"'):]).split())
        assert words in section


@pytest.mark.parametrize("count", [21, -1, True, 2.0, "3"])
def test_a_bad_count_of_further_starts_is_refused_before_any_fit(measured, monkeypatch, count):
    import certkit.physics.calibration as calibration

    def no_fit(*args, **kwargs):
        raise AssertionError("a fit ran")

    monkeypatch.setattr(calibration, "fit", no_fit)
    with pytest.raises(ValueError, match="further starts: expected a whole number from 0 to 20"):
        calibration.calibrate_gear(load_campaign(measured), "left-main", starts=count)


def test_a_knob_whose_nominal_its_bounds_exclude_starts_at_the_nearer_bound(measured,
                                                                            monkeypatch):
    """A nominal its knob's bounds exclude (a rebound orifice wider than the main one has a
    negative damping excess, and its knob's bounds start at 0; here the discharge
    coefficient's bounds are narrowed past the spec's 0.6): the fit starts on the nearer
    bound, and the knob is sized by its nominal."""
    import certkit.physics.calibration as calibration
    from certkit.physics.calibration import KNOBS, Knob

    started = []

    def first_only(single, parameters, **options):
        started.extend(parameters)
        raise calibration.CertkitInputError.single("x", None, "y", "stop after the start")

    outside = Knob(**{**KNOBS["discharge-coefficient"].__dict__, "name": "outside-cd",
                      "bounds": lambda nominal: (0.7, 1.0)})
    monkeypatch.setitem(KNOBS, "outside-cd", outside)
    monkeypatch.setattr(calibration, "fit", first_only)
    with pytest.raises(calibration.CertkitInputError, match="stop after the start"):
        calibration.calibrate_gear(load_campaign(measured), "left-main", knobs=["outside-cd"])
    [parameter] = started
    # the spec's C_d is 0.6, below the bounds [0.7, 1.0]
    assert (parameter.nominal, parameter.lower, parameter.size) == (0.7, 0.7, 0.6)

