"""`certkit audit`: a row per criterion and per finding, JUnit for CI, exit codes."""

import csv
import io
import json
from xml.etree import ElementTree

from typer.testing import CliRunner

from certkit import assess, load_campaign
from certkit.audit import AuditRow, audit_rows, passed, to_junit
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
    assert criteria == [v.id for v in assessment.verdicts] and len(set(criteria)) == 11
    findings = [case.get("name") for case in suites["data quality"].iter("testcase")]
    assert findings == [f.id for f in assessment.findings]
    # a criterion that is not PASS, and an error finding, is a failure with its outcome
    failed = {case.get("name"): case.find("failure").get("type")
              for suite in suites.values() for case in suite.iter("testcase")
              if case.find("failure") is not None}
    assert failed == {**{v.id: v.verdict for v in assessment.verdicts if v.verdict != "PASS"},
                      **{f.id: "error" for f in assessment.findings if f.severity == "error"}}
    assert int(suites["criteria"].get("failures")) == 7     # 4 of the 11 pass, see below
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
    assert "**NOT PASSED**: 4 of 11 criteria pass" in result.output
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
    from certkit.report import results_document

    return results_document(assess(load_campaign(SEED)), {})


def test_a_one_percent_change_in_a_peak_load_is_caught():
    from certkit.baseline import compare

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
    from certkit.baseline import compare

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
