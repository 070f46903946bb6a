"""Bad input: exit code 2, a message naming file, line and key, and no output left behind."""

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from certkit.cli import app

from .conftest import analytic_signals, write_csv

runner = CliRunner()


def run_report(spec: Path, out: Path):
    return runner.invoke(app, ["report", str(spec), "-o", str(out), "--no-model"])


def edit_spec(spec: Path, old: str, new: str) -> None:
    text = spec.read_text(encoding="utf-8")
    assert old in text, f"fixture text {old!r} not found"
    spec.write_text(text.replace(old, new, 1), encoding="utf-8")


def line_of(spec: Path, fragment: str) -> int:
    for number, line in enumerate(spec.read_text(encoding="utf-8").splitlines(), start=1):
        if fragment in line:
            return number
    raise AssertionError(fragment)


def assert_input_error(result, out: Path, *fragments: str) -> None:
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in result.output, f"{fragment!r} not in:\n{result.output}"
    assert not out.exists()
    assert not list(out.parent.glob(f".{out.name}.tmp-*"))


SPEC_CASES = [
    # (old text, new text, key path in message, expected words, line fragment)
    ("drop_height: 300 mm", "drop_height: 0.3 m/s", "runs[0].drop_height",
     'expected a length, got "0.3 m/s"', "drop_height: 0.3 m/s"),
    ("wing_area: 12 m^2", "wing_area: 12", "aircraft.wing_area",
     "expected an area with its unit, got the bare number 12", "wing_area: 12"),
    ("drop_mass: 250 kg", "drop_mas: 250 kg", "runs[0].drop_mas",
     "unknown key", "drop_mas: 250 kg"),
    ("  wing_lift_ratio: 0.667\n", "", "aircraft.wing_lift_ratio",
     "required key is missing", "aircraft:"),
    ("gear_units: [left-main]", "gear_units: [left-mian]", "runs[0].gear_units[0]",
     "unknown gear unit 'left-mian'", "gear_units: [left-mian]"),
    ("requirement_set: 14CFR23-amdt62", "requirement_set: 14CFR23", "certification_basis[0].requirement_set",
     "unknown requirement set '14CFR23'", "requirement_set: 14CFR23"),
    ("file: data/r1.csv", "file: ../outside.csv", "runs[0].data.file",
     "outside the campaign folder", "file: ../outside.csv"),
    ("file: data/r1.csv", "file: data/missing.csv", "runs[0].data.file",
     "not found", "file: data/missing.csv"),
    ("vertical_load: {column: Fz_kN, unit: kN}", "vertical_load: {column: Fz_left, unit: kN}",
     "runs[0].data.gears.left-main.vertical_load.column", "column 'Fz_left' not found",
     "column: Fz_left"),
    ("vertical_load: {column: Fz_kN, unit: kN}", "vertical_load: {column: Fz_kN, unit: mm}",
     "runs[0].data.gears.left-main.vertical_load.unit", "expected a unit of weight", "unit: mm}"),
    ("lift: {method: reduced_mass, ratio: 0.667}", "lift: {method: reduced_mass}",
     "runs[0].lift.ratio", "needs the lift ratio", "lift: {method: reduced_mass}"),
    ("test_type: limit", "test_type: limt", "runs[0].test_type", "input should be",
     "test_type: limt"),
    # 2025 is not a leap year (2025 mod 4 = 1): February has 28 days; 2024 is (mod 4 = 0,
    # mod 100 != 0): 29 days
    ("date: 2025-03-01", "date: 2025-02-30", "document.date",
     '"2025-02-30" is not a date: February 2025 has 28 days', "date: 2025-02-30"),
    ("test_dates: [2025-02-27]", "test_dates: [2024-02-30]", "document.test_dates[0]",
     '"2024-02-30" is not a date: February 2024 has 29 days', "test_dates: [2024-02-30]"),
    ("date: 2025-03-01", "date: 2025-13-01", "document.date",
     '"2025-13-01" is not a date: there is no month 13', "date: 2025-13-01"),
]


@pytest.mark.parametrize("old, new, key, words, line_text", SPEC_CASES,
                         ids=[case[2] + ":" + case[3][:20] for case in SPEC_CASES])
def test_bad_spec_value_names_file_line_and_key(timeseries_campaign, tmp_path, old, new, key,
                                                words, line_text):
    edit_spec(timeseries_campaign, old, new)
    line = line_of(timeseries_campaign, line_text)
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", f"campaign.yaml:{line} {key}:", words)


MISSPELT_KEYS = [
    # (old text, new text, key path of the misspelt key, the key meant)
    ("drop_height: 300 mm", "drop_heigth: 300 mm", "runs[0].drop_heigth", "drop_height"),
    ("wing_area: 12 m^2", "wing_aera: 12 m^2", "aircraft.wing_aera", "wing_area"),
    # an optional key: nothing is missing, the unknown one is still named
    ("file: data/r1.csv", "file: data/r1.csv\n      sampling_rte: 1000 Hz",
     "runs[0].data.sampling_rte", "sampling_rate"),
    # inside a mapping keyed by gear id
    ("vertical_load: {column: Fz_kN, unit: kN}", "vertical_laod: {column: Fz_kN, unit: kN}",
     "runs[0].data.gears.left-main.vertical_laod", "vertical_load"),
]


@pytest.mark.parametrize("old, new, key, meant", MISSPELT_KEYS, ids=[c[3] for c in MISSPELT_KEYS])
def test_misspelt_key_is_one_error_naming_the_likely_key(timeseries_campaign, old, new, key,
                                                         meant):
    edit_spec(timeseries_campaign, old, new)
    typo = key.rsplit(".", 1)[1]
    line = line_of(timeseries_campaign, typo + ":")
    result = runner.invoke(app, ["validate", str(timeseries_campaign)])
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output
    assert f"campaign.yaml:{line} {key}: unknown key {typo!r}: did you mean {meant!r}?" \
        in result.output, result.output
    assert result.output.count("error:") == 1, result.output  # no "missing" error beside it


def test_yaml_syntax_error_names_the_line(timeseries_campaign, tmp_path):
    edit_spec(timeseries_campaign, "drop_height: 300 mm", "drop_height: [300 mm")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "campaign.yaml:", "not valid YAML")


def test_duplicate_key_is_an_error(timeseries_campaign, tmp_path):
    edit_spec(timeseries_campaign, "drop_height: 300 mm", "drop_height: 300 mm\n    drop_height: 250 mm")
    line = line_of(timeseries_campaign, "drop_height: 250 mm")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", f"campaign.yaml:{line}", "duplicate key 'drop_height'")


def data_file(spec: Path) -> Path:
    return spec.parent / "data" / "r1.csv"


def rewrite(spec: Path, change) -> None:
    columns = analytic_signals()
    change(columns)
    write_csv(data_file(spec), columns)


DATA_CASES = [
    # (name, change to the columns, expected words, CSV line of the first bad row or None)
    ("time not increasing", lambda c: c["t_s"].__setitem__(200, c["t_s"][198]),
     "time not increasing", 202),
    ("duplicated time", lambda c: c["t_s"].__setitem__(300, c["t_s"][299]),
     "time duplicated", 302),
    ("sample rate", lambda c: c["t_s"].__imul__(2.0), "sample rate 500 Hz differs", None),
    ("NaN in a channel", lambda c: c["stroke_mm"].__setitem__(150, np.nan),
     "missing or non-numeric", 152),
    ("gap in time", lambda c: c["t_s"].__setitem__(slice(400, None), c["t_s"][400:] + 0.05),
     "gap(s) in time", 402),
    ("clipped load", lambda c: c["Fz_kN"].__setitem__(slice(150, 160), c["Fz_kN"].max() * 1.0)
     or c["Fz_kN"].__setitem__(slice(150, 160), 12.5), "flat at its maximum", 152),
    # 10 x stroke passes 1.2 x 120 mm when 0.8 sin(pi tau/0.12) > 0.144, i.e. tau > 6.95 ms:
    # first at tau = 7 ms, sample 107, CSV line 109; 10·80 mm·sin(7π/120) = 145.8 mm, said in
    # the file's own unit (the column is in mm)
    ("implausible stroke", lambda c: c["stroke_mm"].__imul__(10.0),
     "value 145.8 mm (after scale, sign and offset) is outside the plausible range [", 109),
    # 5 x load: F = 60 kN·sin(π/2·sin(πτ/0.12)) passes 20 x 2600 N = 52 kN first at
    # τ = 28 ms (60·sin(π/2·0.66913) = 52.077 kN), sample 128, CSV line 130; the column is in kN,
    # so is the message
    ("implausible load", lambda c: c["Fz_kN"].__imul__(5.0),
     "value 52.08 kN (after scale, sign and offset) is outside the plausible range "
     "[-0.2600, 52.00] kN", 130),
]


TIME_UNIT_SLIPS = [
    # (factor applied to the seconds in the file, unit declared, rate read in it, unit that
    # fits): the file steps 1 ms, declared 1000 Hz.  1 ms written as 1 and read in s gives
    # 1 Hz; written as 0.001 and read in min, 1/(0.06 s) = 16.6667 Hz; written as 1000 (us)
    # and read in ms, 1/(1 s) = 1 Hz.
    (1000.0, "s", "1 Hz", "ms"),
    (1.0, "min", "16.6667 Hz", "s"),
    (1e6, "ms", "1 Hz", "us"),
]


@pytest.mark.parametrize("factor, declared, rate, fits", TIME_UNIT_SLIPS,
                         ids=[f"{c[1]} for {c[3]}" for c in TIME_UNIT_SLIPS])
def test_time_unit_slip_names_the_unit_that_fits(timeseries_campaign, tmp_path, factor, declared,
                                                 rate, fits):
    rewrite(timeseries_campaign, lambda c: c["t_s"].__imul__(factor))
    edit_spec(timeseries_campaign, "time: {column: t_s, unit: s}",
              f"time: {{column: t_s, unit: {declared}}}")
    line = line_of(timeseries_campaign, "time: {column: t_s")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out",
                       f"campaign.yaml:{line} runs[0].data.time.unit:", "data/r1.csv",
                       f"read in {declared}, give {rate} against the declared 1000 Hz",
                       "the time unit looks wrong", f"read in {fits} they give 1000 Hz")
    assert "waiver" not in result.output  # a unit slip is not a rate to accept


@pytest.mark.parametrize("name, change, words, row", DATA_CASES, ids=[c[0] for c in DATA_CASES])
def test_bad_data_names_file_row_and_channel(timeseries_campaign, tmp_path, name, change, words, row):
    rewrite(timeseries_campaign, change)
    result = run_report(timeseries_campaign, tmp_path / "out")
    where = f"data/r1.csv:{row} " if row else "data/r1.csv "
    assert_input_error(result, tmp_path / "out", where + "runs[0].data.", words)


def test_waived_data_problem_becomes_a_finding(timeseries_campaign, tmp_path):
    rewrite(timeseries_campaign, lambda c: c["t_s"].__imul__(2.0))
    edit_spec(timeseries_campaign, "    inspection: {failure: false}",
              "      waivers: [{check: sample_rate, reason: logger set to 500 Hz by mistake}]\n"
              "    inspection: {failure: false}")
    from certkit import assess, load_campaign
    assessment = assess(load_campaign(timeseries_campaign))
    finding = next(f for f in assessment.findings if f.check == "data-sample-rate")
    assert "logger set to 500 Hz" in finding.message


def test_missing_spec_file(tmp_path):
    result = run_report(tmp_path / "nope.yaml", tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "nope.yaml: file not found")


def test_validate_reports_every_problem_at_once(timeseries_campaign):
    edit_spec(timeseries_campaign, "drop_height: 300 mm", "drop_height: 300")
    edit_spec(timeseries_campaign, "wing_area: 12 m^2", "wing_area: 12 kg")
    result = runner.invoke(app, ["validate", str(timeseries_campaign)])
    assert result.exit_code == 2
    assert "runs[0].drop_height" in result.output and "aircraft.wing_area" in result.output


EXPRESSION_CASES = [
    ("drop_height: 300 mm", "drop_height: 1/0 mm", "write one decimal number and a unit"),
    ("drop_height: 300 mm", "drop_height: 10**10**10 mm", "write one decimal number and a unit"),
    ("drop_height: 300 mm", "drop_height: '300,5 mm'", "write a decimal point, not a comma"),
    ("drop_height: 300 mm", "drop_height: 30 %", "expected a length"),
    ("drop_height: 300 mm", "drop_height: -300 mm", "must be positive"),
    ("design_limit_inertia_load_factor: 5.5", "design_limit_inertia_load_factor: 5.5 g",
     "expected a bare number"),
    ("design_limit_inertia_load_factor: 5.5", "design_limit_inertia_load_factor: -4.4",
     "must be positive"),
    ("sampling_rate: 1000 Hz", "sampling_rate: 60000 rpm", "an angular rate"),
    ("sampling_rate: 1000 Hz", "sampling_rate: 0 Hz", "must be positive"),
    ("date: 2025-03-01", "date: 0", "expected a date as YYYY-MM-DD"),
    ("revision: \"1\"", "revision: 1", "write it in quotes"),
    ("drop_mass_displacement: {column: x_mm, unit: mm}",
     "drop_mass_displacement: {column: x_mm, unit: mm, scale: .nan}", "finite number"),
    ("drop_mass_displacement: {column: x_mm, unit: mm}",
     "drop_mass_displacement: {column: x_mm, unit: mm, scale: 0}", "scale must not be zero"),
    ("wing_area: 12 m^2", "wing_area: 1e-300 m^2",
     "outside the magnitudes certkit computes with (zero, or 1e-12 to 1e12 m**2)"),
    ("wing_area: 12 m^2", "wing_area: 1e-11 m^2", "not a plausible number"),
    ("diameter: 380 mm", "diameter: -380 mm", "must be positive"),
]


@pytest.mark.parametrize("old, new, words", EXPRESSION_CASES, ids=[c[1] for c in EXPRESSION_CASES])
def test_values_that_are_not_plain_quantities_are_refused(timeseries_campaign, tmp_path, old, new,
                                                          words):
    edit_spec(timeseries_campaign, old, new)
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "campaign.yaml:", words)


def test_audit_threshold_above_100_percent_is_refused(timeseries_campaign, tmp_path):
    edit_spec(timeseries_campaign, "certkit: 1\n", "certkit: 1\naudit: {bottoming_margin: 200 %}\n")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "campaign.yaml:2 audit.bottoming_margin:",
                       "must be at most 1")


def test_empty_spec_file_says_what_it_needs(tmp_path):
    spec = tmp_path / "campaign.yaml"
    spec.write_text("# nothing yet\n", encoding="utf-8")
    result = run_report(spec, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "the file is empty", "certkit, campaign")


def test_complex_yaml_key_is_an_input_error(timeseries_campaign, tmp_path):
    edit_spec(timeseries_campaign, "aircraft:\n", "aircraft:\n  ? [a, b]\n  : x\n")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "a key must be a plain name")


def test_non_utf8_spec_names_the_line(timeseries_campaign, tmp_path):
    content = timeseries_campaign.read_bytes().replace(b"Test rig", b"Test r\xe9ig")
    timeseries_campaign.write_bytes(content)
    line = content[: content.index(b"\xe9")].count(b"\n") + 1
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", f"campaign.yaml:{line}", "not UTF-8")


def test_decimal_commas_in_a_comma_separated_file_name_the_line(timeseries_campaign, tmp_path):
    path = data_file(timeseries_campaign)
    header, *rows = path.read_text(encoding="utf-8").splitlines()
    path.write_text("\n".join([header] + [row.replace(".", ",") for row in rows]) + "\n",
                    encoding="utf-8")
    # line 2 is t = 0: 0.0, 0.0, 0.0, 0.0, -9.80665, -170.96675 (x = -V0*T0 + g*T0^2/2 in
    # mm) all have a decimal point, so each of the 6 fields splits in two: 12 fields
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "data/r1.csv:2",
                       "line 2 has 12 fields, the header has 6",
                       "a decimal comma splits a number in two")


def test_mixed_decimal_marks_are_refused_naming_both_lines(timeseries_campaign, tmp_path):
    path = data_file(timeseries_campaign)
    lines = path.read_text(encoding="utf-8").replace(",", ";").splitlines()
    lines = [line.replace(".", ",") if number != 10 else line
             for number, line in enumerate(lines, start=1)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "data/r1.csv:10",
                       "semicolon-separated file writes a number with a decimal comma on line 2 "
                       "and one with a decimal point on line 10")


def test_row_with_extra_fields_names_its_line(timeseries_campaign, tmp_path):
    path = data_file(timeseries_campaign)
    lines = path.read_text(encoding="utf-8").splitlines()
    lines[9] += ",1.0"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "data/r1.csv:10", "line 10 has 7 fields, the header has 6")


def test_data_path_that_is_a_folder(timeseries_campaign, tmp_path):
    (timeseries_campaign.parent / "data" / "folder.csv").mkdir()
    edit_spec(timeseries_campaign, "file: data/r1.csv", "file: data/folder.csv")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "is a folder, not a file")


def test_symlink_leaving_the_campaign_folder_is_refused(timeseries_campaign, tmp_path):
    outside = tmp_path / "outside.csv"
    outside.write_bytes(data_file(timeseries_campaign).read_bytes())
    (timeseries_campaign.parent / "data" / "link.csv").symlink_to(outside)
    edit_spec(timeseries_campaign, "file: data/r1.csv", "file: data/link.csv")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "outside the campaign folder")


YAML_CASES = [
    ("aircraft:\n", "aircraft:\n  x: &a [*a]\n", "anchors and aliases"),
    ("gear_units: [left-main]", "gear_units: !!set {left-main}",
     'explicit YAML tags ("!!set") are not supported'),
    ("aircraft:\n", "aircraft:\n  3: 2\n", "keys must be text"),
    ("vertical_load: {column: Fz_kN, unit: kN}", "vertical_load: {column: Fz_kN, unit: 1/0 kN}",
     "expected a unit of weight"),
    ("time: {column: t_s, unit: s}", "time: {column: t_s, unit: '10**10**10 s'}",
     "expected a unit of time"),
    ("lift: {method: reduced_mass, ratio: 0.667}", "lift: none", "expected a mapping"),
]


@pytest.mark.parametrize("old, new, words", YAML_CASES, ids=[c[2] for c in YAML_CASES])
def test_unsupported_yaml_and_unit_forms(timeseries_campaign, tmp_path, old, new, words):
    edit_spec(timeseries_campaign, old, new)
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "campaign.yaml", words)


def test_deeply_nested_yaml_is_an_input_error(timeseries_campaign, tmp_path):
    edit_spec(timeseries_campaign, "aircraft:\n", "aircraft:\n  x: " + "[" * 5000 + "\n")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "campaign.yaml")


def test_inclination_beyond_45_degrees_is_refused(timeseries_campaign, tmp_path):
    edit_spec(timeseries_campaign, "inclination: 0 deg", "inclination: 180 deg")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "gear_units[0].strut.inclination",
                       "must be at most 45 deg")


def test_text_timestamps_in_a_csv_time_column(timeseries_campaign, tmp_path):
    path = data_file(timeseries_campaign)
    lines = path.read_text(encoding="utf-8").splitlines()
    lines[1] = "2024-01-01T00:00:00," + lines[1].split(",", 1)[1]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "data/r1.csv:2", "holds text such as")


def test_repeated_column_names_are_refused(timeseries_campaign, tmp_path):
    path = data_file(timeseries_campaign)
    text = path.read_text(encoding="utf-8").replace("acc_ms2", "Fz_kN", 1)
    path.write_text(text, encoding="utf-8")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "data/r1.csv:1", "repeated in the header: Fz_kN")


def test_too_few_rows_points_at_the_spec(timeseries_campaign, tmp_path):
    path = data_file(timeseries_campaign)
    path.write_text("\n".join(path.read_text(encoding="utf-8").splitlines()[:3]) + "\n",
                    encoding="utf-8")
    line = line_of(timeseries_campaign, "file: data/r1.csv")
    result = run_report(timeseries_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", f"campaign.yaml:{line} runs[0].data.file",
                       "has 2 data row(s); at least 3 are needed")


def test_zero_reported_energies_do_not_crash_the_audit(seed_copy, tmp_path):
    text = seed_copy.read_text(encoding="utf-8")
    text = text.replace("strut_energy: 596.72 J, tyre_energy: 172.67 J",
                        "strut_energy: 0 J, tyre_energy: 0 J")
    text = text.replace("strut_energy: 1060.74 J, tyre_energy: 250.06 J",
                        "strut_energy: 0 J, tyre_energy: 0 J")
    text = text.replace("strut_energy: 1305.97 J, tyre_energy: 356.36 J",
                        "strut_energy: 0 J, tyre_energy: 0 J")
    seed_copy.write_text(text, encoding="utf-8")
    result = run_report(seed_copy, tmp_path / "out")
    assert result.exit_code == 0, result.output
    from certkit import assess, load_campaign
    findings = assess(load_campaign(seed_copy)).findings
    assert any(f.check == "efficiency-not-positive-strut" and f.gear == "left-main"
               for f in findings)


def test_an_unknown_held_out_run_is_an_input_error(physics_campaign, tmp_path):
    edit_spec(physics_campaign, "  effects: [rebound-orifice, seal-friction]",
              "  effects: [rebound-orifice, seal-friction]\n"
              "  identification: {held_out: [D3OO]}")
    result = run_report(physics_campaign, tmp_path / "out")
    assert_input_error(result, tmp_path / "out", "model.identification.held_out[0]",
                       "unknown run 'D3OO'", f"campaign.yaml:{line_of(physics_campaign, 'D3OO')}")


def test_an_input_error_crosses_a_process_boundary_whole():
    """An input error raised in a worker process reaches the parent with its problems (file,
    line, key, message), not as one problem per letter of its message.  Checked in a fresh
    interpreter that imports only certkit.errors (a module the CLI imports may change how
    exceptions pickle)."""
    import subprocess
    import sys

    check = """
import pickle
from certkit.errors import CertkitInputError, DataInputError, Problem
error = CertkitInputError([Problem("campaign.yaml", 12, "runs[0].drop_height",
                                   "expected a length, found 'tall'"),
                           Problem("data/D1.csv", None, "", "empty file")])
again = pickle.loads(pickle.dumps(error))
assert type(again) is CertkitInputError and again.problems == error.problems
assert str(again) == ("campaign.yaml:12 runs[0].drop_height: expected a length, found "
                      "'tall'\\ndata/D1.csv: empty file"), repr(str(again))
data = pickle.loads(pickle.dumps(DataInputError("gamma", "expected > 0, found -1")))
assert type(data) is DataInputError and data.problems == [
    Problem("argument", None, "gamma", "expected > 0, found -1")]
"""
    done = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
