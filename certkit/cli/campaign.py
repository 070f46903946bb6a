"""Commands on a campaign's compliance evidence: validate, report, audit, schema, sets."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Annotated

import typer
from rich.status import Status

from certkit.cli.app import SpecArgument, bad_option, command, err, out
from certkit.compliance.engine import assess
from certkit.evidence.audit import (audit_rows, baseline_rows, passed, to_csv, to_json, to_junit,
                                    to_markdown)
from certkit.evidence.comparison import compare, read_baseline
from certkit.evidence.pipeline import report_campaign
from certkit.evidence.results_document import results_document
from certkit.outputs import check_file_target, write_text_atomically, writing_failure
from certkit.spec import requirement_sets
from certkit.spec.campaign import load_campaign
from certkit.spec.schema import json_schema


@command()
def validate(spec: SpecArgument) -> None:
    """Check a campaign spec and its data files; print what was found wrong."""
    campaign = load_campaign(spec)
    runs = len(campaign.spec.runs)
    with_data = sum(series is not None for series in campaign.series.values())
    out.print(f"{spec}: valid — {runs} run(s), {with_data} with time series, "
              f"{len(campaign.inputs)} input file(s)")


@command()
def report(spec: SpecArgument,
           output: Annotated[Path, typer.Option("-o", "--output", metavar="FOLDER",
                                                help="the folder to write the report into")] = Path("out"),
           strict: Annotated[bool, typer.Option(
               "--strict", help="exit 1 unless every criterion passes and the data-quality "
                                "audit finds no error, as the audit command's exit code (a "
                                "criterion NOT SHOWN is not a pass)")] = False,
           model: Annotated[bool, typer.Option(
               "--model/--no-model", help="add the drop model's appendices: calibration, "
                                          "identification and gap diagnosis")] = True,
           cache: Annotated[bool, typer.Option(
               "--cache/--no-cache", help="take the drop model's evidence from the user's "
                                          "cache when the inputs and the code that makes it "
                                          "are unchanged")] = True) -> None:
    """Write the evidence: report.html, report.pdf (PDF/A-3b), results.json and
    tables/*.csv."""
    status = Status("loading campaign", console=err) if err.is_terminal else None
    if status:
        status.start()
    try:
        def progress(message: str) -> None:
            if status:
                status.update(message)
            else:              # a log (CI): one plain line per step, so it never sits silent
                err.print(f"certkit report: {message}")

        assessment, _ = report_campaign(load_campaign(spec), output, model=model,
                                        cache=cache, progress=progress)
    finally:
        if status:
            status.stop()
    counts, findings = assessment.counts(), assessment.finding_counts()
    out.print(f"{assessment.outcome}: {counts['PASS']} pass, {counts['FAIL']} fail, "
              f"{counts['NOT SHOWN']} not shown; data-quality findings: {findings['error']} "
              f"error, {findings['warning']} warning")
    out.print(f"wrote {output}/report.pdf, report.html, results.json, tables/")
    if strict and not passed(audit_rows(assessment)):   # the audit's rule, from its home
        raise typer.Exit(1)


def _write_both(files: list[tuple[Path, str]]) -> None:
    """Both files or neither: a failed second write puts back what the first replaced (or
    removes it, if there was nothing)."""
    written: list[tuple[Path, bytes | None]] = []
    try:
        for path, content in files:
            before = path.read_bytes() if path.is_file() else None
            write_text_atomically(path, content)
            written.append((path, before))
    except OSError as problem:
        for done, before in written:
            if before is None:
                done.unlink(missing_ok=True)
            else:
                done.write_bytes(before)
        raise writing_failure(problem, path, "cannot write the audit", key="") from None


@command()
def audit(spec: SpecArgument,
          format: Annotated[str, typer.Option(
              "--format", metavar="FORMAT",
              help="the table on standard output (or -o): md (Markdown), csv or json")] = "md",
          output: Annotated[Path | None, typer.Option(
              "-o", "--output", metavar="FILE", help="write the table to FILE instead")] = None,
          junit: Annotated[Path | None, typer.Option(
              "--junit", metavar="FILE", help="also write JUnit XML to FILE (a test case per row)")] = None,
          baseline: Annotated[Path | None, typer.Option(
              "--baseline", metavar="RESULTS",
              help="an earlier results.json: report every number that drifted, every "
                   "criterion added or removed, every verdict changed")] = None,
          tolerance: Annotated[float, typer.Option(
              metavar="SHARE",
              help="with --baseline: the relative drift allowed before a number counts as "
                   "changed, e.g. 1e-6")] = 1e-9,
          ) -> None:
    """Audit tables for CI: one row per criterion per run and per data-quality finding (and
    per change since a baseline); exit 0 when every criterion passes, no finding is an error and nothing
    changed, 1 otherwise, 2 on bad input."""
    writers = {"md": None, "csv": to_csv, "json": to_json}
    if format not in writers:
        bad_option("format", "md, csv or json", repr(format))
    campaign = load_campaign(spec)
    inputs = [item.path for item in campaign.inputs] + ([baseline] if baseline else [])
    for key, path in (("output", output), ("junit", junit)):
        if path is not None:
            check_file_target(path, inputs, f"--{key}")
    if output is not None and junit is not None and output.resolve() == junit.resolve():
        bad_option("junit", "another file than --output", str(junit))
    assessment = assess(campaign)
    rows = audit_rows(assessment)
    if baseline is not None:
        if not tolerance >= 0:
            bad_option("tolerance", "a share ≥ 0", tolerance)
        earlier = read_baseline(baseline)
        rows += baseline_rows(compare(results_document(assessment, {}), earlier, tolerance))
    title = f"{campaign.spec.campaign.id} ({spec.name})"
    units = campaign.spec.report.units
    text = to_markdown(rows, title, units) if format == "md" else writers[format](rows)
    files = [(output, text)] if output is not None else []
    if junit is not None:
        files.append((junit, to_junit(rows, title, units)))
    _write_both(files)
    if output is None:
        sys.stdout.write(text)
    raise typer.Exit(0 if passed(rows) else 1)


@command()
def schema() -> None:
    """Print the JSON Schema of the campaign spec (for editors and CI)."""
    sys.stdout.write(json.dumps(json_schema(), indent=2, ensure_ascii=False) + "\n")


@command()
def sets() -> None:
    """List the shipped requirement sets."""
    for set_id in requirement_sets.available():
        rules = requirement_sets.load(set_id)
        marker = " (values to be confirmed against the licensed standard)" if rules.to_confirm else ""
        out.print(f"{set_id}: {rules.title}{marker}")
