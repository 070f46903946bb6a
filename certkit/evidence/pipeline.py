"""The whole evidence of one campaign, made in one call: the assessment, the drop model's
evidence when asked for, and the report with its results and tables written to a folder.

The CLI's ``report`` and the archive both make their evidence through :func:`report_campaign`,
so the two cannot drift apart.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from certkit.compliance.engine import assess
from certkit.evidence.report import render_report
from certkit.spec.campaign import Campaign


def make_evidence(campaign: Campaign, *, model: bool = True,
                  progress: Callable[[str], None] | None = None):
    """The assessment of ``campaign`` and, unless ``model`` is False, the drop model's
    evidence (calibration, identification, gap diagnosis; a
    :class:`~certkit.evidence.model_evidence.ModelEvidence`), else None."""
    progress = progress or (lambda message: None)
    progress("assessing")
    assessment = assess(campaign)
    if not model:
        return assessment, None
    # Lazy on purpose: the model stage (numba kernel, scipy's optimisers) adds about 0.5 s
    # to every CLI start-up (python -X importtime -c "import certkit.cli": 0.56 s for
    # certkit, 0.58 s more with the model stage), which validate, audit and
    # report --no-model do not need.
    from certkit.evidence.model_evidence import model_evidence

    return assessment, model_evidence(campaign, progress=progress)


def report_campaign(campaign: Campaign, folder: str | Path, *, model: bool = True,
                    progress: Callable[[str], None] | None = None):
    """:func:`make_evidence`, then the report with its results and tables written into
    ``folder`` (all or nothing); returns the assessment and the model evidence."""
    assessment, evidence = make_evidence(campaign, model=model, progress=progress)
    render_report(assessment, folder, progress, evidence)
    return assessment, evidence
