"""Hostile and careless input (issue 16): whatever a user types or a logger writes, certkit
answers with an input error (exit 2, file, line, key, a bounded echo) or works; it never
reports its own bug (exit 3) for it.

One reproducer per crash class found by fuzzing, then property tests (hypothesis,
derandomised so CI is deterministic) over the loaders the fuzz script
benchmarks/fuzz_inputs.py drives for longer.
"""

from __future__ import annotations

import datetime as dt
import os
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from typer.testing import CliRunner

from certkit.cli import app
from certkit.units import QuantityError, parse_quantity, parse_unit

from . import hostile_inputs as hostile
from .conftest import analytic_signals, write_csv

runner = CliRunner()

#: No line of an error may be longer than this: every echoed value is cut to ~60 characters.
LONGEST_LINE = 400


def edit_spec(spec: Path, old: str, new: str) -> None:
    text = spec.read_text(encoding="utf-8")
    assert old in text, f"fixture text {old!r} not found"
    spec.write_text(text.replace(old, new, 1), encoding="utf-8")


def refused(command: str, spec: Path, *fragments: str):
    """Run ``certkit <command> spec`` in-process: exit 2, no traceback, each fragment in the
    message, no line longer than LONGEST_LINE (a crash leaves exit code 1 here)."""
    result = runner.invoke(app, [command, str(spec)])
    assert result.exit_code == 2, (result.exit_code, result.output, result.exception)
    assert "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in result.output, f"{fragment!r} not in:\n{result.output}"
    assert max(len(line) for line in result.output.splitlines()) <= LONGEST_LINE, result.output
    return result.output


def with_waivers(spec: Path, *checks: str) -> None:
    waivers = ", ".join(f"{{check: {check}, reason: accepted}}" for check in checks)
    edit_spec(spec, "drop_mass_displacement: {column: x_mm, unit: mm}\n",
              f"drop_mass_displacement: {{column: x_mm, unit: mm}}\n"
              f"      waivers: [{waivers}]\n")


def rewrite_data(spec: Path, change) -> None:
    columns = analytic_signals()
    change(columns)
    write_csv(spec.parent / "data" / "r1.csv", columns)


# --------------------------------------------------------------------------- 1. YAML reader
def test_a_control_character_in_the_spec_is_an_input_error(timeseries_campaign):
    edit_spec(timeseries_campaign, "title: Analytic", "title: \x07Analytic")
    refused("validate", timeseries_campaign, "campaign.yaml:2", "control character",
            "U+0007")


@pytest.mark.parametrize("tagged", ["!!int A", "!!float x", "!!bool maybe",
                                    "!!timestamp 2024-13-15", "!!map A", "!!str text"])
def test_explicit_yaml_tags_are_refused(timeseries_campaign, tagged):
    edit_spec(timeseries_campaign, "model: Test aircraft", f"model: {tagged}")
    refused("validate", timeseries_campaign, "campaign.yaml:14", "YAML tags",
            tagged.split()[0])


def test_a_yaml_merge_key_is_refused_in_words(timeseries_campaign):
    # found probing: `<<: {model: X}` said "could not determine a constructor for the tag
    # 'tag:yaml.org,2002:merge'"
    edit_spec(timeseries_campaign, "aircraft:\n", "aircraft:\n  <<: {model: X}\n")
    refused("validate", timeseries_campaign, "campaign.yaml:14", "YAML merge keys (<<) are "
                                                                 "not supported")


# --------------------------------------------------------------------------- 2. huge numbers
@pytest.mark.parametrize("old, new", [
    ("wing_lift_ratio: 0.667", "wing_lift_ratio: " + "9" * 5000),
    ('revision: "1"', "revision: " + "9" * 5000),
    ('revision: "1"', "revision: 0x" + "f" * 4000),
    ("wing_lift_ratio: 0.667", "wing_lift_ratio: " + "9" * 401),
    ("wing_lift_ratio: 0.667", "wing_lift_ratio: '" + "9" * 401 + "'"),
    ("drop_height: 300 mm", "drop_height: " + "9" * 401 + " mm"),
], ids=["5000-digit ratio", "5000-digit text", "4000 hex digits", "401-digit ratio",
        "401-digit quoted ratio", "401-digit length"])
def test_a_huge_number_in_the_spec_is_an_input_error(timeseries_campaign, old, new):
    edit_spec(timeseries_campaign, old, new)
    refused("validate", timeseries_campaign, "campaign.yaml:")


@pytest.mark.parametrize("values", ["integers", "decimals"])
def test_a_huge_number_in_a_data_cell_is_an_input_error(timeseries_campaign, values):
    # a column of whole numbers is read as Python integers: one of 400 digits cannot be a
    # float (a logger writing integer counts)
    path = timeseries_campaign.parent / "data" / "r1.csv"
    lines = path.read_text(encoding="utf-8").splitlines()
    for number in range(1, len(lines)):
        cells = lines[number].split(",")
        if values == "integers":
            cells[1] = str(round(float(cells[1])))
        if number == 5:
            cells[1] = "9" * 400
        lines[number] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    refused("audit", timeseries_campaign, "data/r1.csv")


# --------------------------------------------------------------------------- 3. units
@pytest.mark.parametrize("value", ["200 mm^0", "200 mm/dB", "200 mm*dB", "3 km^99*km^99"])
def test_a_unit_pint_cannot_use_is_an_input_error(timeseries_campaign, value):
    edit_spec(timeseries_campaign, "drop_height: 300 mm", f"drop_height: {value}")
    refused("validate", timeseries_campaign, "runs[0].drop_height", "expected a length")


def test_a_column_unit_to_the_power_zero_is_an_input_error(timeseries_campaign):
    edit_spec(timeseries_campaign, "time: {column: t_s, unit: s}",
              "time: {column: t_s, unit: s^0}")
    refused("validate", timeseries_campaign, "runs[0].data.time.unit", "expected a unit of time")


def test_a_logarithmic_unit_in_an_angle_says_what_is_wrong():
    with pytest.raises(QuantityError) as caught:
        parse_quantity("3 deg*dB", "angle")
    assert "assertion" not in str(caught.value) and "3 deg*dB" in str(caught.value)
    assert "logarithmic" in str(caught.value)


# --------------------------------------------------------------------------- 4. file names
def test_a_data_file_name_too_long_for_the_system_is_an_input_error(timeseries_campaign):
    edit_spec(timeseries_campaign, "file: data/r1.csv", "file: data/" + "x" * 300 + ".csv")
    refused("validate", timeseries_campaign, "runs[0].data.file", "(309 characters)", "File name too long")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_named_as_data_file_is_not_a_regular_file(timeseries_campaign):
    os.mkfifo(timeseries_campaign.parent / "data" / "pipe.csv")
    edit_spec(timeseries_campaign, "file: data/r1.csv", "file: data/pipe.csv")
    refused("validate", timeseries_campaign, "runs[0].data.file", "not a regular file")


# --------------------------------------------------------------------------- 5. Parquet
def test_a_parquet_file_with_two_level_column_names_is_an_input_error(timeseries_campaign):
    import pandas as pd

    frame = pd.DataFrame(analytic_signals())
    frame.columns = pd.MultiIndex.from_tuples([(name, "value") for name in frame.columns])
    frame.to_parquet(timeseries_campaign.parent / "data" / "r1.parquet")
    edit_spec(timeseries_campaign, "file: data/r1.csv", "file: data/r1.parquet")
    refused("validate", timeseries_campaign, "data/r1.parquet", "column names")


# --------------------------------------------------------------------------- 6. validate -> assess
def test_a_load_channel_entirely_empty_under_a_gaps_waiver_is_an_input_error(
        timeseries_campaign):
    with_waivers(timeseries_campaign, "gaps")
    rewrite_data(timeseries_campaign, lambda c: c["Fz_kN"].__setitem__(slice(None), np.nan))
    refused("audit", timeseries_campaign, "data/r1.csv", "Fz_kN")


def test_a_subnormal_reported_load_is_an_input_error(timeseries_campaign):
    edit_spec(timeseries_campaign, "inspection: {failure: false}",
              "reported: {gears: {left-main: {peak_vertical_load: 5e-324 kgf}}}")
    refused("audit", timeseries_campaign, "peak_vertical_load", "5e-324 kgf")


@pytest.mark.parametrize("step", [1e-200, 1e5])
def test_time_steps_no_logger_takes_are_an_input_error_even_with_the_rate_waived(
        timeseries_campaign, step):
    with_waivers(timeseries_campaign, "sample_rate")
    rewrite_data(timeseries_campaign, lambda c: c.__setitem__("t_s", np.arange(600) * step))
    refused("audit", timeseries_campaign, "runs[0].data.time.column", "sample rate")


# --------------------------------------------------------------------------- 7. dates
def test_a_document_date_before_1970_renders_the_pdf(monkeypatch):
    """Where HarfBuzz cannot subset (an older system library), WeasyPrint subsets with
    fontTools, which stamps each font with SOURCE_DATE_EPOCH: forced here."""
    import weasyprint.pdf.fonts

    from certkit.evidence.render import render_pdf

    monkeypatch.setattr(weasyprint.pdf.fonts, "harfbuzz_subset", None)

    pdf = render_pdf("<html><body><p>Issued 1903-12-31</p></body></html>", [],
                     dt.date(1903, 12, 31))
    assert pdf.startswith(b"%PDF")


@pytest.mark.parametrize("date, words", [
    ("1899-12-31", "a year from 1900 to 2200"), ("2201-01-01", "a year from 1900 to 2200"),
    ("'20240115'", "YYYY-MM-DD"), ("'2024-W03-1'", "YYYY-MM-DD"),
])
def test_dates_are_yyyy_mm_dd_within_bounds(timeseries_campaign, date, words):
    edit_spec(timeseries_campaign, "date: 2025-03-01", f"date: {date}")
    refused("validate", timeseries_campaign, "campaign.yaml:6 document.date", words)


def test_a_document_date_of_1903_is_accepted(timeseries_campaign):
    edit_spec(timeseries_campaign, "date: 2025-03-01", "date: 1903-12-31")
    result = runner.invoke(app, ["validate", str(timeseries_campaign)])
    assert result.exit_code == 0, result.output


# --------------------------------------------------------------------------- 8. bounded input
@pytest.mark.parametrize("length", [20_000, 100_000])
def test_a_long_number_is_refused_at_once_with_a_bounded_echo(length):
    started = time.perf_counter()
    with pytest.raises(QuantityError) as caught:
        parse_quantity("1" * length + "!", "length")
    assert time.perf_counter() - started < 0.5
    assert len(str(caught.value)) < 300 and f"({length + 1} characters)" in str(caught.value)


def test_a_long_drop_height_is_an_input_error_with_a_bounded_echo(timeseries_campaign):
    edit_spec(timeseries_campaign, "drop_height: 300 mm", "drop_height: " + "1" * 20_000 + "!")
    refused("validate", timeseries_campaign, "runs[0].drop_height", "(20001 characters)")


# --------------------------------------------------------------------------- minor items
def test_control_characters_in_a_csv_header_are_shown_escaped(timeseries_campaign):
    path = timeseries_campaign.parent / "data" / "r1.csv"
    text = path.read_text(encoding="utf-8")
    path.write_text(text.replace("t_s", "t\x00_s\x1b[31m", 1), encoding="utf-8")
    output = refused("validate", timeseries_campaign, "column 't_s' not found",
                     r"t\x00_s\x1b[31m")
    assert "\x00" not in output and "\x1b" not in output


@pytest.mark.parametrize("value", ["-3 dB", "3 dB", "1 Np"])
def test_a_ratio_in_a_logarithmic_unit_is_refused(value):
    with pytest.raises(QuantityError, match="logarithmic"):
        parse_quantity(value, "dimensionless")


# --------------------------------------------------------------------------- properties
def examples(count: int) -> settings:
    """Derandomised (the same examples on every run, no example database): CI is
    deterministic; the longer random search is benchmarks/fuzz_inputs.py."""
    return settings(derandomize=True, database=None, deadline=None, max_examples=count,
                    suppress_health_check=list(HealthCheck))


@examples(300)
@given(text=hostile.quantity_texts(), kind=hostile.KIND_NAMES)
def test_the_quantity_parser_raises_only_quantity_errors(text, kind):
    assert hostile.outcome(parse_quantity, text, kind) != "crash"
    assert hostile.outcome(parse_unit, text, kind if kind != "angle" else "length") != "crash"


@pytest.fixture(scope="module")
def spec_folder(tmp_path_factory) -> Path:
    return hostile.campaign_folder(tmp_path_factory.mktemp("spec-fuzz"))


@examples(60)
@given(mutation=hostile.spec_mutations())
def test_the_spec_loader_raises_only_input_errors_and_assess_survives(spec_folder, mutation):
    """What the loader accepts, the assessment (audit, report) takes too."""
    result = hostile.try_spec(spec_folder, mutation, assess=True)
    assert result.kind != "crash", result.detail


@examples(60)
@given(mutation=hostile.data_mutations())
def test_the_data_loader_raises_only_input_errors_and_assess_survives(spec_folder, mutation):
    result = hostile.try_data(spec_folder, mutation, assess=True)
    assert result.kind != "crash", result.detail


@examples(40)
@given(mutation=hostile.parquet_mutations())
def test_the_parquet_loader_raises_only_input_errors_and_assess_survives(spec_folder, mutation):
    """Column types, nulls, odd and two-level names, timestamps, zero rows, row groups,
    damaged bytes: read, or refused with an input error."""
    result = hostile.try_data(spec_folder, mutation, assess=True)
    assert result.kind != "crash", result.detail


@pytest.fixture(scope="module")
def model_folder(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("model-fuzz")


@pytest.mark.slow
@examples(5)   # 5: CI's 20-minute limit; benchmarks/fuzz_inputs.py runs 40
@given(mutation=hostile.model_mutations())
def test_what_validate_accepts_the_drop_model_stages_survive(model_folder, mutation):
    """The simulated drop-model campaign, its spec or a run's data mutated, through what
    `certkit report` runs: assess, calibration, identification, gap diagnosis (a few
    seconds to a minute per accepted input; benchmarks/fuzz_inputs.py runs more)."""
    result = hostile.try_model(model_folder, mutation, gap=True)
    assert result.kind != "crash", result.detail


def test_an_unknown_top_level_key_is_an_input_error(timeseries_campaign):
    # found by the spec fuzzer: an unknown key at the top level crashed the spelling hint
    edit_spec(timeseries_campaign, "certkit: 1\n", "certkit: 1\nrunz: []\n")
    refused("validate", timeseries_campaign, "campaign.yaml:2 runz: unknown key")


@pytest.mark.parametrize("value", ["-1e308", "1e13"])
def test_a_data_value_beyond_the_magnitudes_certkit_computes_with_is_not_waivable(
        timeseries_campaign, value):
    # found by the data fuzzer: -1e308 m/s^2 under an implausible-range waiver overflowed
    with_waivers(timeseries_campaign, "implausible_range")
    path = timeseries_campaign.parent / "data" / "r1.csv"
    lines = path.read_text(encoding="utf-8").splitlines()
    for number in range(1, len(lines)):
        cells = lines[number].split(",")
        cells[4] = value
        lines[number] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    refused("audit", timeseries_campaign, "data/r1.csv:2 runs[0].data.drop_mass_acceleration",
            "beyond the magnitudes certkit computes with")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_named_as_the_spec_is_refused_not_waited_on(tmp_path):
    os.mkfifo(tmp_path / "campaign.yaml")
    refused("validate", tmp_path / "campaign.yaml", "not a regular file")


@pytest.mark.parametrize("content, words", [
    ("[" * 100_000 + "]" * 100_000, "nested too deeply"),
    ('{"format": ' + "9" * 5000 + "}", "an integer of 5000 digits"),
    (b"\xff\xfe{}", "not UTF-8"),
], ids=["deep", "long integer", "not UTF-8"])
def test_a_hostile_baseline_file_is_an_input_error(timeseries_campaign, tmp_path, content,
                                                    words):
    baseline = tmp_path / "baseline.json"
    if isinstance(content, bytes):
        baseline.write_bytes(content)
    else:
        baseline.write_text(content, encoding="utf-8")
    result = runner.invoke(app, ["audit", str(timeseries_campaign), "--baseline",
                                 str(baseline)])
    assert result.exit_code == 2, (result.output, result.exception)
    assert words in result.output and "baseline.json" in result.output


@pytest.mark.parametrize("content, words", [
    ("[" * 100_000 + "]" * 100_000, "nested too deeply"),
    ('{"kind": ' + "9" * 5000 + "}", "an integer of 5000 digits"),
], ids=["deep", "long integer"])
def test_a_hostile_blind_check_record_is_an_input_error(timeseries_campaign, content, words):
    (timeseries_campaign.parent / "blind.json").write_text(content, encoding="utf-8")
    edit_spec(timeseries_campaign, "certkit: 1\n",
              "certkit: 1\nmodel: {gap: {blind_check: blind.json}}\n")
    refused("validate", timeseries_campaign, "model.gap.blind_check", words)


def _parquet_cell(kind: str, count: int):
    import decimal

    import pandas as pd

    return {"list": [[1.0]] * count, "struct": [{"a": 1}] * count,
            "bytes": [b"ab"] * count, "decimal": [decimal.Decimal("1.5")] * count,
            "timedelta": pd.to_timedelta(np.ones(count), unit="s"),
            "nullable": pd.array([1] * (count - 1) + [None], dtype="Int64")}[kind]


@pytest.mark.parametrize("kind", ["list", "struct", "bytes", "decimal", "timedelta",
                                  "nullable"])
def test_a_parquet_load_column_of_any_type_is_read_or_refused(timeseries_campaign, kind):
    import pandas as pd

    frame = pd.DataFrame(analytic_signals())
    frame["Fz_kN"] = _parquet_cell(kind, len(frame))
    frame.to_parquet(timeseries_campaign.parent / "data" / "r1.parquet")
    edit_spec(timeseries_campaign, "file: data/r1.csv", "file: data/r1.parquet")
    result = runner.invoke(app, ["audit", str(timeseries_campaign)])
    assert result.exit_code in (0, 1, 2) and result.exception is None or \
        isinstance(result.exception, SystemExit), (result.output, result.exception)


def test_a_date_shaped_text_value_survives_the_simulation(physics_campaign, tmp_path):
    # found by the validate -> simulate chain: a report number written 2023-02-29 is text to
    # certkit, but the simulation re-read the spec with PyYAML's own date resolver
    edit_spec(physics_campaign, "report_number: PHYS-0001", "report_number: 2023-02-29")
    result = runner.invoke(app, ["simulate", str(physics_campaign), "-o", str(tmp_path / "s"),
                                 "--no-noise"])
    assert result.exit_code == 0, (result.output, result.exception)


# --------------------------------------------------------------------------- outputs at inputs
@pytest.mark.parametrize("command, option, target", [
    ("audit", "-o", "campaign.yaml"), ("audit", "-o", "data/r1.csv"),
    ("audit", "--junit", "data/r1.csv"), ("calibrate", "--json", "campaign.yaml"),
    ("identify", "--json", "data/r1.csv"), ("audit", "-o", "data")])
def test_a_single_output_file_named_at_an_input_is_refused_before_anything_is_written(
        timeseries_campaign, command, option, target):
    # found probing: `audit -o campaign.yaml` replaced the spec with the audit table (exit 1)
    folder = timeseries_campaign.parent
    before = {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    result = runner.invoke(app, [command, str(timeseries_campaign), option,
                                 str(folder / target)])
    assert result.exit_code == 2, (result.output, result.exception)
    expected = "is a folder" if target == "data" else "writing there would replace it"
    assert f"{folder / target} {option if option != '-o' else '--output'}: " in result.output
    assert expected in result.output, result.output
    assert {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()} == before


def test_the_audit_and_its_junit_table_in_one_file_are_refused(timeseries_campaign, tmp_path):
    result = runner.invoke(app, ["audit", str(timeseries_campaign), "-o", str(tmp_path / "a"),
                                 "--junit", str(tmp_path / "a")])
    assert result.exit_code == 2 and "--junit: expected another file than --output" in \
        result.output, result.output
    assert not (tmp_path / "a").exists()


@pytest.mark.parametrize("encoding, line, byte", [("utf-16", 1, "0xff"), ("latin-1", 1, "0xd1")])
def test_a_csv_file_not_in_utf8_says_so_with_the_line_and_byte(timeseries_campaign, encoding,
                                                               line, byte):
    # found probing: a spreadsheet's UTF-16 or Latin-1 export was refused with Python's
    # "'utf-8' codec can't decode byte 0xff in position 0: invalid start byte"
    path = timeseries_campaign.parent / "data" / "r1.csv"
    text = path.read_text(encoding="utf-8").replace("Fz_kN", "Fz_kÑ")
    path.write_bytes(text.encode(encoding))
    edit_spec(timeseries_campaign, "column: Fz_kN", "column: Fz_kÑ")
    refused("validate", timeseries_campaign, f"data/r1.csv:{line}: expected UTF-8 text, found "
                                             f"byte {byte} on line {line}", "save the file as "
                                                                            "UTF-8")


@pytest.mark.parametrize("path", ["data\\\\r1.csv", "'C:\\\\data\\\\r1.csv'"])
def test_a_windows_path_to_a_data_file_is_refused_saying_how_to_write_it(timeseries_campaign,
                                                                         path):
    # found probing: a path written with backslashes said only "not found"
    edit_spec(timeseries_campaign, "file: data/r1.csv", f"file: {path}")
    refused("validate", timeseries_campaign, "runs[0].data.file", "not found",
            "relative to the spec's folder with '/'")


def test_a_parquet_file_repeating_a_column_name_says_so(timeseries_campaign):
    # found by the Parquet fuzzer: pyarrow's "Multiple matches for FieldRef.Name(Fz_kN) in
    # t_s: double\nFz_kN: double\n…" (exit 2, but no word of what to change)
    path = timeseries_campaign.parent / "data" / "r1.parquet"
    path.write_bytes(hostile.ParquetMutation("name", 4, hostile.PARQUET_NAMES.index("Fz_kN"))
                     .apply())
    edit_spec(timeseries_campaign, "file: data/r1.csv", "file: data/r1.parquet")
    refused("validate", timeseries_campaign,
            "data/r1.parquet: column name(s) repeated in the header: Fz_kN")


@pytest.mark.parametrize("name", ["campaign.yaml", "data/r1.txt"])
def test_a_data_file_of_a_format_certkit_does_not_read_is_named_at_its_key(
        timeseries_campaign, name):
    # found probing: the spec itself (or a .txt copy of the data) named as a run's data file
    # was refused naming that file, but not the spec's line and key that named it
    if name.endswith(".txt"):
        (timeseries_campaign.parent / name).write_bytes(
            (timeseries_campaign.parent / "data" / "r1.csv").read_bytes())
    edit_spec(timeseries_campaign, "file: data/r1.csv", f"file: {name}")
    output = refused("validate", timeseries_campaign, "runs[0].data.file",
                     "not in a format certkit reads", ".csv, .parquet, .pq",
                     f"found {Path(name).suffix!r}")
    line = next(i for i, text in enumerate(
        timeseries_campaign.read_text(encoding="utf-8").splitlines(), 1) if f"file: {name}" in text)
    assert f"{timeseries_campaign.name}:{line} runs[0].data.file" in output


def test_a_parquet_file_with_a_column_name_that_is_not_utf8_gets_a_parquet_message(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    from certkit.errors import CertkitInputError
    from certkit.spec.rundata import _read_table

    good = tmp_path / "good.parquet"
    pq.write_table(pa.table({"time_\u00e9": [0.0, 0.001], "load": [1.0, 2.0]}), good,
                   store_schema=False)
    raw = good.read_bytes()
    assert raw.count("\u00e9".encode()) >= 1
    bad = tmp_path / "bad.parquet"
    bad.write_bytes(raw.replace("\u00e9".encode(), b"\xfc\xfc"))    # 2 bytes, not UTF-8
    with pytest.raises(CertkitInputError) as caught:
        _read_table(bad, "data/bad.parquet")
    message = str(caught.value)
    assert "not UTF-8 text" in message and "data/bad.parquet" in message
    assert "line" not in message and "spreadsheet" not in message     # not the CSV advice
