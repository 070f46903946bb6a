"""Rendering the evidence: results.json, CSV tables, self-contained HTML and PDF/A-3b.

Python prepares plain data (strings already formatted with their display units);
the Jinja2 templates only lay it out.  Outputs are written into a temporary folder
beside the target and moved into place at the end, so a failed or interrupted run
leaves no partial report.
"""

from __future__ import annotations

from pathlib import Path

from certkit.compliance.assessment import Assessment
from certkit.evidence.provenance import provenance
from certkit.evidence.render import render_html, render_pdf
from certkit.evidence.results_document import results_json, write_tables
from certkit.evidence.view import build_view
from certkit.outputs import staged_folder


def _write_outputs(assessment: Assessment, folder: Path, progress, model) -> None:
    campaign = assessment.campaign
    record = provenance(campaign.inputs)
    progress("computing results")
    results_bytes = results_json(assessment, model, record)
    (folder / "results.json").write_bytes(results_bytes)
    write_tables(assessment, folder / "tables", model)
    progress("drawing figures and laying out HTML")
    html = render_html(build_view(assessment, record, model))
    (folder / "report.html").write_text(html, encoding="utf-8")
    progress("writing PDF/A-3b")
    attachments = [(f"inputs/{item.name}", item.path.read_bytes(), "Source")
                   for item in campaign.inputs]
    attachments.append(("results.json", results_bytes, "Data"))
    (folder / "report.pdf").write_bytes(render_pdf(html, attachments, campaign.spec.document.date))



#: What render_report writes; an existing folder holding anything else is not replaced.
TABLES = ("verdicts", "findings", "values", "comparisons", "model", "identification", "gap",
          "gap_shrink")



REPORT_FILES = {"report.html", "report.pdf", "results.json"} | {f"tables/{name}.csv"
                                                                for name in TABLES}



def render_report(assessment: Assessment, out_dir: str | Path, progress=None,
                  model=None) -> Path:
    """Write report.html, report.pdf, results.json and ``tables/*.csv`` into ``out_dir``.

    ``model``: the governing-equation model evidence
    (:func:`certkit.evidence.model_evidence.model_evidence`); without it the section says the model
    was not run.

    Everything is written into a temporary sibling folder and moved into place at
    the end; on any failure (or interruption) nothing is left behind and an
    existing ``out_dir`` is untouched.  A target that holds the campaign's inputs,
    the current folder or files certkit did not write is refused (CertkitInputError).
    """
    progress = progress or (lambda message: None)
    inputs = [item.path for item in assessment.campaign.inputs]
    with staged_folder(out_dir, inputs, REPORT_FILES) as staging:
        _write_outputs(assessment, staging, progress, model)
    return Path(out_dir)
