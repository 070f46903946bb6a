"""Identification on a synthetic campaign: every model scored by free-run simulation on
the held-out drop, which is used for nothing else."""

import re
import warnings

import numpy as np
import pytest

from certkit import load_campaign
from certkit.gear_identification import identify_gear
from certkit.ident.search_space import SearchEdgeWarning
from certkit.physics.synthetic import simulate_campaign


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    from .conftest import PHYSICS_SPEC, write_campaign

    root = tmp_path_factory.mktemp("identification")
    spec = write_campaign(root / "truth", PHYSICS_SPEC)
    return simulate_campaign(load_campaign(spec), root / "runs", seed=5)


@pytest.fixture(scope="module")
def identified(synthetic):
    """The identification and the categories of the warnings it showed."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = identify_gear(load_campaign(synthetic), "left-main")
    return result, [warning.category for warning in caught]


@pytest.fixture(scope="module")
def result(identified):
    return identified[0]


def test_every_model_is_scored_on_the_held_out_drop_in_free_run(result):
    assert result.training == ("D200", "D250") and result.held_out == ("D300",)
    models = {s.model for s in result.scores if s.protocol == "held-out"}
    assert models == {"governing equation, nominal", "governing equation, calibrated",
                      "Hammerstein", "NARX", "Wiener (small-signal)", "Wiener (BLA)"}
    assert all(s.run == "D300" for s in result.scores)
    assert {(s.model, s.output) for s in result.scores if s.protocol == "paper"} >= {
        ("Hammerstein", "stroke"), ("NARX", "tyre"), ("Wiener (BLA)", "stroke")}
    # one-step prediction is kept apart from the free-run scores and is not worse
    for model, output, run, one_step in result.one_step:
        free_run = next(s for s in result.scores if (s.model, s.output, s.protocol) ==
                        (model, output, "held-out"))
        assert one_step <= free_run.rmse


def test_the_true_model_family_predicts_the_held_out_drop_to_the_noise(result):
    # the runs were simulated by the spec's own model with 0.05 mm travel noise: once
    # calibrated on D200 and D250, the governing equation predicts D300 to about that
    for output in ("stroke", "tyre"):
        score = next(s for s in result.scores if s.model == "governing equation, calibrated"
                     and s.output == output)
        assert score.rmse < 0.1  # mm


def test_a_tuned_point_on_the_edge_of_the_protocols_search_is_a_note_not_a_warning(identified):
    # before: the drop protocol's search edges were silenced (gear_identification.quiet_edges)
    result, shown = identified
    assert SearchEdgeWarning not in shown
    notes = [n for n in result.notes if "lies on the edge of the protocol's search" in n]
    hammerstein = [n for n in notes if ", Hammerstein: " in n]
    assert hammerstein, result.notes
    # the protocol's Hammerstein ranges (the identification page): γ in [10, 10⁶], σ² in
    # [0.1, 1000] kN²; a point on an edge is at one of those ends, and the note names its key
    ends = {"lower": {"γ": "10.00", "σ²": "0.1000 kN²"}, "upper": {"γ": "1.000×10⁶",
                                                                   "σ²": "1000 kN²"}}
    for note in hammerstein:
        found = re.findall(r"(γ|σ²) = ([^,]+), its (lower|upper) end", note)
        assert found, note
        for symbol, value, side in found:
            assert value == ends[side][symbol], note
            key = {"γ": "gamma", "σ²": "sigma2"}[symbol]
            assert f"model.identification.hammerstein.{key}" in note


@pytest.mark.slow
def test_the_held_out_drop_does_not_influence_any_fitted_model(synthetic, result):
    # change only D300's recorded stroke: every block fitted on the training runs must come
    # out bit for bit the same, only the held-out scores move
    text = synthetic.read_text(encoding="utf-8")
    runs = synthetic.parent / "data" / "D300.csv"
    lines = runs.read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    column = header.index("left-main_stroke_mm")
    changed = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        cells[column] = f"{float(cells[column]) * 1.05:.5f}"
        changed.append(",".join(cells))
    runs.write_text("\n".join(changed) + "\n", encoding="utf-8")
    try:
        again = identify_gear(load_campaign(synthetic), "left-main")
    finally:
        runs.write_text("\n".join(lines) + "\n", encoding="utf-8")
        synthetic.write_text(text, encoding="utf-8")
    for key, block in result.linear_blocks.items():
        assert np.array_equal(block.a_, again.linear_blocks[key].a_), key
    for key, (grid, curve) in result.nonlinearities.items():
        assert np.array_equal(curve, again.nonlinearities[key][1]), key
    before = {(s.model, s.output): s.rmse for s in result.scores if s.protocol == "held-out"}
    after = {(s.model, s.output): s.rmse for s in again.scores if s.protocol == "held-out"}
    assert any(after[k] != before[k] for k in before if k[1] == "stroke")


def test_json_document_is_plain_and_finite(result):
    import json

    from certkit.gear_identification import Identification, identification_document

    document = identification_document(Identification([result], "plant"))
    text = json.dumps(document, allow_nan=False)
    gear = json.loads(text)["gear_units"][0]
    assert gear["held_out"] == ["D300"]
    assert {x["protocol"] for x in gear["free_run"]} == {"paper", "held-out"}
    assert all(x["model"] in ("Hammerstein", "NARX") for x in gear["one_step"])


def test_spec_chooses_held_out_runs_orders_and_fixed_hyper_parameters(synthetic):
    import yaml

    text = synthetic.read_text(encoding="utf-8")
    raw = yaml.safe_load(text)
    raw["model"]["identification"] = {
        "held_out": ["D250"],
        "hammerstein": {"na": 2, "nb": 2, "gamma": 1e4, "sigma2": 20},
        "wiener": {"na": 2, "nb": 2, "gamma": 1e4, "sigma2": 10},
        "narx": {"na": 1, "nb": 1, "gamma": 1e3, "sigma2": 5}}
    synthetic.write_text(yaml.safe_dump(raw, sort_keys=False), encoding="utf-8")
    try:
        chosen = identify_gear(load_campaign(synthetic), "left-main")
    finally:
        synthetic.write_text(text, encoding="utf-8")
    assert chosen.training == ("D200", "D300") and chosen.held_out == ("D250",)
    blocks = [block for (route, _), block in chosen.linear_blocks.items()]
    assert blocks and all(block.a_.size == 2 and block.b_.size == 2 for block in blocks)
    assert all(s.run == "D250" for s in chosen.scores)
    assert not [n for n in chosen.notes if "edge of the protocol's search" in n]  # not tuned


def test_identify_command_needs_two_recorded_drops(physics_campaign):
    from typer.testing import CliRunner

    from certkit.cli import app

    outcome = CliRunner().invoke(app, ["identify", str(physics_campaign)])
    assert outcome.exit_code == 2 and "nothing to identify" in outcome.output


def test_a_gear_not_identified_says_which_runs_were_too_short(timeseries_campaign):
    # conftest's analytic run: 0.6 s logged, touchdown at 0.1 s, so 0.5 s after it (the
    # first sample past the touchdown threshold is at 0.101 s: 0.499 s, shown as 0.499)
    from certkit import load_campaign
    from certkit.gear_identification import identify

    result = identify(load_campaign(timeseries_campaign))
    assert result.gears == []
    assert result.skipped == ["left-main: 0 usable drop(s), two needed (run R1 has 0.499 s "
                              "recorded after touchdown, identification needs 1 s)"]


def test_the_static_nonlinearity_figure_draws_only_what_is_a_function_of_the_load(result):
    """A Wiener block whose static gain is not determined is scaled to unit ‖b‖: its z is
    no force, so it is left off the load axis (drawn there it ran to −4500 kN and squeezed
    the Hammerstein curve into a vertical line), and the caption says so; a block with a
    gain is drawn and the caption says it was scaled to unit gain."""
    from dataclasses import replace
    from types import SimpleNamespace

    from certkit.evidence.figures import identification_figures
    from certkit.spec.schema import DisplayUnits

    key = next(k for k in result.linear_blocks if k[1] == "stroke")
    for determined in (True, False):
        blocks = {k: SimpleNamespace(gain_determined=True) for k in result.linear_blocks}
        blocks[key] = SimpleNamespace(gain_determined=determined)
        figure = identification_figures(replace(result, linear_blocks=blocks),
                                        DisplayUnits())[0]
        left_out = f"Not drawn: {key[0]} for the strut stroke"
        assert (left_out in figure["caption"]) is (not determined), figure["caption"]
        assert "the block scaled to unit static gain" in figure["caption"]


def test_a_tuning_that_fails_still_shows_its_other_warnings_and_notes_its_edges():
    """The search edges of a tuning are notes of the report; any other warning is shown,
    also when the tuning then raises (before, the error dropped them)."""
    import warnings
    from types import SimpleNamespace

    from certkit.gear_identification import OUTPUTS, _edges_as_notes
    from certkit.ident.search_space import SearchEdge, SearchEdgeWarning

    result = SimpleNamespace(notes=[])
    edge = SearchEdge("gamma", "lower", 10.0, 10.0, "widen it downwards")
    with pytest.warns(UserWarning, match="ill-conditioned"), \
            pytest.raises(RuntimeError, match="no fold"):
        with _edges_as_notes(result, OUTPUTS[0], "Hammerstein", "hammerstein"):
            warnings.warn("ill-conditioned kernel", UserWarning)
            warnings.warn(SearchEdgeWarning("on the edge", (edge,)))
            raise RuntimeError("no fold could be scored")
    assert len(result.notes) == 1 and "γ = 10.00, its lower end" in result.notes[0]
    assert "model.identification.hammerstein.gamma" in result.notes[0]
