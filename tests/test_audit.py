"""`certkit audit`: a row per criterion and per finding, JUnit for CI, exit codes."""

import csv
import io
import json
from xml.etree import ElementTree

from typer.testing import CliRunner

from certkit import assess, load_campaign
from certkit.evidence.audit import AuditRow, audit_rows, passed, to_junit
from certkit.cli import app

from .conftest import SEED

runner = CliRunner()


def test_junit_parses_and_lists_every_criterion_and_finding(tmp_path):
    junit = tmp_path / "audit.xml"
    result = runner.invoke(app, ["audit", str(SEED), "--junit", str(junit), "--format", "json"])
    # the example's compliance is NOT SHOWN and its data have energy errors (README): exit 1
    assert result.exit_code == 1, result.output
    assessment = assess(load_campaign(SEED))
    root = ElementTree.parse(junit).getroot()
    suites = {s.get("name"): s for s in root.iter("testsuite")}
    criteria = [case.get("name") for case in suites["criteria"].iter("testcase")]
    # F2245: height 1 + energy 2 gears; 14 CFR 23: 725a 1, 725b 2, 725c 1 (never assessed),
    # 725f 2, 727a 1, 723b 1, 473g 1, 727b 1 (no reserve drop: one NOT SHOWN row); 726 does
    # not apply
    assert criteria == [v.id for v in assessment.verdicts] and len(set(criteria)) == 13
    findings = [case.get("name") for case in suites["data quality"].iter("testcase")]
    assert findings == [f.id for f in assessment.findings]
    # a criterion that is not PASS, and an error finding, is a failure with its outcome
    failed = {case.get("name"): case.find("failure").get("type")
              for suite in suites.values() for case in suite.iter("testcase")
              if case.find("failure") is not None}
    assert failed == {**{v.id: v.verdict for v in assessment.verdicts if v.verdict != "PASS"},
                      **{f.id: "error" for f in assessment.findings if f.severity == "error"}}
    assert int(suites["criteria"].get("failures")) == 9     # 4 of the 13 pass, see below
    # the JSON on standard output has the same rows, values in SI
    rows = json.loads(result.output)
    height = next(r for r in rows if r["id"] == "CFR23.725a-limit-drop-height/D300")
    # 23.725(a): h = 3.6·√(W/S) in, W/S = 1430 lb / 140.85 ft² → 11.47 in = 0.2914 m
    assert height["outcome"] == "PASS" and height["unit"] == "m"
    assert abs(height["limit"] - 3.6 * (1430 / 140.85) ** 0.5 * 0.0254) < 1e-3
    assert abs(height["margin"] - (0.3 - height["limit"])) < 1e-12


def test_markdown_summary_counts_and_lists_what_does_not_pass():
    result = runner.invoke(app, ["audit", str(SEED)])
    assert result.exit_code == 1
    # passes: the drop height under F2245 and 23.725(a), and 23.725(b) for both gears
    assert "**NOT PASSED**: 4 of 13 criteria pass" in result.output
    assert "## Not passing" in result.output and "CFR23.727a-reserve-drop-height" in result.output


def test_csv_has_a_row_per_criterion_and_finding_and_the_same_bytes_every_time(tmp_path):
    first, second = tmp_path / "a.csv", tmp_path / "b.csv"
    for path in (first, second):
        assert runner.invoke(app, ["audit", str(SEED), "--format", "csv", "-o",
                                   str(path)]).exit_code == 1
    assert first.read_bytes() == second.read_bytes()
    rows = list(csv.DictReader(io.StringIO(first.read_text(encoding="utf-8"))))
    assessment = assess(load_campaign(SEED))
    assert len(rows) == len(assessment.verdicts) + len(assessment.findings)
    assert len({r["id"] for r in rows}) == len(rows)


def _row(kind, outcome):
    return AuditRow("x", kind, "c", "t", None, None, None, None, None, "1", outcome, "")


def test_exit_status_rule():
    assert passed([_row("criterion", "PASS"), _row("finding", "warning")])
    assert not passed([_row("criterion", "NOT SHOWN")])      # not shown is not a pass
    assert not passed([_row("criterion", "FAIL")])
    assert not passed([_row("criterion", "PASS"), _row("finding", "error")])
    root = ElementTree.fromstring(to_junit([_row("criterion", "PASS")], "t").split("\n", 1)[1])
    assert root.find("testsuite").get("failures") == "0"


def test_bad_input_exits_2(tmp_path):
    result = runner.invoke(app, ["audit", str(SEED), "--format", "xml"])
    assert result.exit_code == 2 and "--format: expected md, csv or json" in result.output
    missing = tmp_path / "nope.yaml"
    result = runner.invoke(app, ["audit", str(missing)])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert not list(tmp_path.iterdir())


def test_rows_keep_the_assessments_order():
    assessment = assess(load_campaign(SEED))
    rows = audit_rows(assessment)
    assert [r.id for r in rows] == [v.id for v in assessment.verdicts] + [
        f.id for f in assessment.findings]


# --------------------------------------------------------------------------- baseline
BASELINE = SEED.parent / "audit-baseline" / "results.json"


def _current():
    from certkit.evidence.results_document import results_document

    return results_document(assess(load_campaign(SEED)), {})


def test_a_one_percent_change_in_a_peak_load_is_caught():
    from certkit.evidence.comparison import compare

    current = _current()
    baseline = json.loads(json.dumps(current))
    gear = next(g for r in baseline["runs"] if r["id"] == "D300" for g in r["gears"]
                if g["gear"] == "left-main")
    peak = next(v for v in gear["values"] if v["key"] == "F_peak")
    peak["value"] *= 1.01
    changes = compare(current, baseline, tolerance=1e-6)
    assert [(c.kind, c.path) for c in changes] == [("drifted", "runs/D300/left-main/F_peak")]
    # now / baseline − 1 = 1/1.01 − 1
    assert f"{100 * (1 / 1.01 - 1):+.4g} %" in changes[0].detail
    # below the tolerance nothing is flagged
    peak["value"] = peak["value"] / 1.01 * (1 + 1e-12)
    assert compare(current, baseline, tolerance=1e-9) == []


def test_verdicts_changed_added_and_removed_are_caught():
    from certkit.evidence.comparison import compare

    current = _current()
    baseline = json.loads(json.dumps(current))
    baseline["verdicts"][0]["verdict"] = "FAIL"                  # was PASS
    dropped = baseline["verdicts"].pop(1)                         # now "added"
    baseline["verdicts"].append(dict(dropped, id="OLD-criterion"))  # now "removed"
    kinds = {(c.kind, c.path) for c in compare(current, baseline, 1e-9)}
    first = current["verdicts"][0]["id"]
    assert ("verdict changed", f"criterion {first}") in kinds
    assert ("added", f"criterion {dropped['id']}") in kinds
    assert ("removed", "criterion OLD-criterion") in kinds


def test_the_example_matches_its_committed_baseline_and_a_tampered_one_fails(tmp_path):
    """What the project's CI runs: the audit of the example against its committed baseline
    (the example is not compliant, so the exit code is 1 either way; the rows tell)."""
    result = runner.invoke(app, ["audit", str(SEED), "--baseline", str(BASELINE),
                                 "--format", "json"])
    assert result.exit_code == 1
    assert [r for r in json.loads(result.output) if r["kind"] == "baseline"] == []
    document = json.loads(BASELINE.read_text(encoding="utf-8"))
    document["design"][0]["value"] *= 1.01
    tampered = tmp_path / "results.json"
    tampered.write_text(json.dumps(document), encoding="utf-8")
    junit = tmp_path / "audit.xml"
    result = runner.invoke(app, ["audit", str(SEED), "--baseline", str(tampered),
                                 "--junit", str(junit)])
    assert "1 change(s) since the baseline" in result.output
    suites = {s.get("name"): s for s in ElementTree.parse(junit).getroot().iter("testsuite")}
    assert suites["baseline"].get("failures") == "1"


def test_a_baseline_that_is_not_a_results_file_exits_2(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json", encoding="utf-8")
    result = runner.invoke(app, ["audit", str(SEED), "--baseline", str(bad)])
    assert result.exit_code == 2 and "not JSON" in result.output and "bad.json" in result.output
    bad.write_text(json.dumps({"format": "something else"}), encoding="utf-8")
    result = runner.invoke(app, ["audit", str(SEED), "--baseline", str(bad)])
    assert result.exit_code == 2 and "certkit-results/1" in result.output


def test_a_missing_baseline_beside_an_existing_output_file_is_bad_input(tmp_path):
    # the check that -o is not an input compared the output with a baseline that does not
    # exist, and that crashed as a certkit bug (exit 3)
    table = tmp_path / "audit.md"
    table.write_text("an earlier table\n", encoding="utf-8")
    missing = tmp_path / "missing.json"
    result = runner.invoke(app, ["audit", str(SEED), "-o", str(table), "--baseline",
                                 str(missing)])
    assert result.exit_code == 2
    assert "missing.json" in result.output and "cannot be read" in result.output
    assert table.read_text(encoding="utf-8") == "an earlier table\n"


def test_a_failed_write_leaves_no_partial_output(tmp_path):
    table = tmp_path / "audit.md"
    junit = tmp_path / "missing-folder" / "audit.xml"      # cannot be written
    result = runner.invoke(app, ["audit", str(SEED), "-o", str(table), "--junit", str(junit)])
    assert result.exit_code == 2 and "cannot write the audit" in result.output
    assert "Traceback" not in result.output and list(tmp_path.iterdir()) == []


def test_table_values_are_not_rounded(tmp_path):
    path = tmp_path / "a.csv"
    runner.invoke(app, ["audit", str(SEED), "--format", "csv", "-o", str(path)])
    rows = {r["id"]: r for r in csv.DictReader(io.StringIO(path.read_text(encoding="utf-8")))}
    verdict = next(v for v in assess(load_campaign(SEED)).verdicts
                   if v.id == "CFR23.725b-effective-weight/D300/left-main")
    assert float(rows[verdict.id]["value"]) == verdict.value    # exactly, not to 10 digits


def test_new_findings_changed_severities_and_the_outcome_are_caught():
    from certkit.evidence.comparison import compare

    current = _current()
    baseline = json.loads(json.dumps(current))
    error = next(f for f in baseline["findings"] if f["severity"] == "error")
    error["severity"] = "warning"                       # an error that was a warning
    extra = baseline["findings"].pop()                  # a finding new since the baseline
    baseline["outcome"] = "COMPLIANT"
    changes = {(c.kind, c.path): (c.before, c.after) for c in compare(current, baseline, 1e-9)}
    assert changes == {
        ("severity changed", f"finding {error['id']}"): ("warning", "error"),
        ("added", f"finding {extra['id']}"): (None, extra["severity"]),
        ("outcome changed", "campaign outcome"): ("COMPLIANT", "COMPLIANCE NOT SHOWN"),
    }


def test_a_malformed_baseline_is_bad_input_not_a_crash(tmp_path):
    document = json.loads(BASELINE.read_text(encoding="utf-8"))
    for mangle, where in ((lambda d: d["verdicts"][0].pop("id"), "'id'"),
                          (lambda d: d["design"][0].update(value="12 kN"), "design/"),
                          (lambda d: d["findings"][0].pop("severity"), "missing or malformed"),
                          (lambda d: d.update(runs={}), "runs: expected a list")):
        bad = json.loads(json.dumps(document))
        mangle(bad)
        path = tmp_path / "bad.json"
        path.write_text(json.dumps(bad), encoding="utf-8")
        result = runner.invoke(app, ["audit", str(SEED), "--baseline", str(path)])
        assert result.exit_code == 2, result.output
        assert where in result.output and "bad.json" in result.output


def test_a_repeated_finding_gets_its_own_id():
    from types import SimpleNamespace

    from certkit.compliance.findings import add as _add

    assessment = SimpleNamespace(findings=[])
    for channel in ("load", "stroke", "tyre"):   # one check, one run, three channels
        _add(assessment, "data-clipping", "warning", "D300", None, f"{channel} clipped")
    assert [f.id for f in assessment.findings] == [
        "QA/data-clipping/D300", "QA/data-clipping/D300#2", "QA/data-clipping/D300#3"]


RESERVE_RUN = """\
  - id: R2
    test_type: reserve
    gear_units: [left-main]
    drop_height: {height}
    drop_mass: 250 kg
    lift: {{method: reduced_mass, ratio: 0.667}}
    reported:
      gears:
        left-main: {{strut_stroke: 110 mm, tyre_deflection: 40 mm, peak_vertical_load: 12 kN}}
    inspection: {{failure: {failure}}}
"""


def _reserve_campaign(tmp_path, height: str, failure: str, basis: str = "14CFR23-amdt62"):
    """The timeseries campaign with a reserve-energy run R2 from ``height``."""
    from .conftest import TIMESERIES_SPEC, analytic_signals, write_campaign, write_csv

    folder = tmp_path / f"c-{height.replace(' ', '')}-{failure}-{basis}"
    (folder / "data").mkdir(parents=True)
    write_csv(folder / "data" / "r1.csv", analytic_signals())
    text = TIMESERIES_SPEC.replace("requirement_set: 14CFR23-amdt62",
                                   f"requirement_set: {basis}")
    return write_campaign(folder, text + RESERVE_RUN.format(height=height, failure=failure))


def _audit_exit(tmp_path, height: str, failure: str, basis: str = "14CFR23-amdt62"):
    import subprocess
    import sys

    spec = _reserve_campaign(tmp_path, height, failure, basis)
    completed = subprocess.run([sys.executable, "-m", "certkit.cli", "audit", str(spec),
                                "--format", "json"], capture_output=True, text=True,
                               timeout=300)
    rows = {r["id"]: r for r in json.loads(completed.stdout)} if completed.stdout else {}
    return completed.returncode, rows


def test_exit_0_when_everything_passes_and_1_on_a_fail_through_the_entry_point(tmp_path):
    # 600 kg on 12 m²: W/S = 10.24 lb/ft², limit drop h = 3.6·√(W/S) in = 292.6 mm (R1 drops
    # 300 mm); reserve drop 1.44·h = 421.4 mm
    w_over_s = (600 / 0.45359237) / (12 / 0.3048 ** 2)
    reserve = 1.44 * 3.6 * w_over_s ** 0.5 * 0.0254
    assert round(reserve * 1000, 1) == 421.4
    # under ASTM F2245 every criterion passes: exit 0
    status, rows = _audit_exit(tmp_path, "450 mm", "false", "ASTM-F2245")
    assert status == 0 and {r["outcome"] for r in rows.values() if r["kind"] == "criterion"} \
        == {"PASS"}
    # under 14 CFR 23 every criterion certkit assesses passes, but 23.725(c) (attitude and
    # drag loads) is never shown by certkit: exit 1, and it is the only row that fails
    status, rows = _audit_exit(tmp_path, "450 mm", "false")
    failing = {i for i, r in rows.items() if r["kind"] == "criterion" and r["outcome"] != "PASS"}
    assert status == 1 and failing == {"CFR23.725c-attitude-and-drag"}
    status, rows = _audit_exit(tmp_path, "400 mm", "false")      # below the reserve height
    assert status == 1
    row = rows["CFR23.727a-reserve-drop-height/R2"]
    assert row["outcome"] == "FAIL" and abs(row["limit"] - reserve) < 1e-6
    assert abs(row["margin"] - (0.4 - reserve)) < 1e-6
    status, rows = _audit_exit(tmp_path, "450 mm", "true")       # the gear failed
    assert status == 1 and rows["CFR23.723b-reserve-no-failure/R2"]["outcome"] == "FAIL"


def test_report_strict_exits_by_the_audits_rule(tmp_path):
    # before: report --strict exited 0 on COMPLIANCE NOT SHOWN, where the audit exits 1
    # (a criterion NOT SHOWN is not a pass); the campaigns of the test above
    # (requirement values to confirm: the audit passes them, and so does --strict)
    for basis, expected, outcome in (("ASTM-F2245", 0, "COMPLIANT SUBJECT TO CONFIRMATION"),
                                     ("14CFR23-amdt62", 1, "COMPLIANCE NOT SHOWN")):
        spec = _reserve_campaign(tmp_path, "450 mm", "false", basis)
        result = runner.invoke(app, ["report", str(spec), "-o", str(tmp_path / basis),
                                     "--strict", "--no-model"])
        assert result.exit_code == expected, result.output
        assert f"\n{outcome}: " in f"\n{result.output}", result.output
        assert (tmp_path / basis / "report.pdf").exists()   # written whatever the exit


def test_junit_stays_well_formed_with_a_control_character_in_a_message():
    row = AuditRow("QA/x/R1", "finding", "QA", "x", "R1", None, None, None, None, "", "error",
                   "logger note: \x01 \x1b[31m red \x7f end")
    root = ElementTree.fromstring(to_junit([row], "T\x02"))
    failure = root.find("testsuite/testcase/failure")
    assert failure.text == "error: logger note: \ufffd \ufffd[31m red \x7f end"


def test_a_failed_junit_write_puts_back_the_table_it_replaced(tmp_path):
    table = tmp_path / "audit.md"
    table.write_text("the earlier audit\n", encoding="utf-8")
    junit = tmp_path / "missing-folder" / "audit.xml"      # cannot be written
    result = runner.invoke(app, ["audit", str(SEED), "-o", str(table), "--junit", str(junit)])
    assert result.exit_code == 2 and "cannot write the audit" in result.output
    assert table.read_text(encoding="utf-8") == "the earlier audit\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["audit.md"]


def test_written_tables_are_as_readable_as_the_umask_allows(tmp_path):
    import os

    mask = os.umask(0o022)
    try:
        runner.invoke(app, ["audit", str(SEED), "-o", str(tmp_path / "a.md"), "--junit",
                            str(tmp_path / "a.xml")])
    finally:
        os.umask(mask)
    for name in ("a.md", "a.xml"):
        assert (tmp_path / name).stat().st_mode & 0o777 == 0o644, name


def test_a_baseline_with_nan_an_overflowing_number_or_a_numeric_id_is_bad_input(tmp_path):
    text = BASELINE.read_text(encoding="utf-8")
    document = json.loads(text)
    first = document["design"][0]
    cases = [
        text.replace(json.dumps(first["value"]), "NaN", 1),
        text.replace(json.dumps(first["value"]), "1" + "0" * 400, 1),
        json.dumps(dict(document, verdicts=[dict(document["verdicts"][0], id=5)])),
    ]
    for number, content in enumerate(cases):
        path = tmp_path / f"bad{number}.json"
        path.write_text(content, encoding="utf-8")
        result = runner.invoke(app, ["audit", str(SEED), "--baseline", str(path)])
        assert result.exit_code == 2, (number, result.output)
        assert f"bad{number}.json" in result.output
