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
