"""The whole evidence of one campaign, made in one call: the assessment, the drop model's
evidence when asked for, and the report with its results and tables written to a folder.

The CLI's ``report`` and the archive both make their evidence through :func:`report_campaign`,
so the two cannot drift apart.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from certkit.compliance.engine import assess
from certkit.evidence import cache as evidence_cache
from certkit.evidence.report import render_report
from certkit.spec.campaign import Campaign


def make_evidence(campaign: Campaign, *, model: bool = True, cache: bool = True,
                  progress: Callable[[str], None] | None = None):
    """The assessment of ``campaign`` and, unless ``model`` is False, the drop model's
    evidence (calibration, identification, gap diagnosis; a
    :class:`~certkit.evidence.model_evidence.ModelEvidence`), else None.

    With ``cache``, the drop model's evidence is taken from the user's cache when the
    campaign's inputs and the code that makes it are unchanged
    (:mod:`certkit.evidence.cache`), and kept there when it is made."""
    progress = progress or (lambda message: None)
    progress("assessing")
    assessment = assess(campaign)
    if not model:
        return assessment, None
    entry = evidence_cache.key(campaign, "model evidence") if cache else None
    if entry is not None:
        kept = evidence_cache.load(entry)
        if kept is not None:
            progress("drop-model evidence unchanged: taken from the cache "
                     f"({evidence_cache.cache_folder()}, --no-cache makes it again)")
            _say_what_is_missing(kept, progress)
            return assessment, kept
    # Lazy on purpose: the model stage (numba kernel, scipy's optimisers) adds about 0.5 s
    # to every CLI start-up (python -X importtime -c "import certkit.cli": 0.56 s for
    # certkit, 0.58 s more with the model stage), which validate, audit and
    # report --no-model do not need.
    from certkit.evidence.model_evidence import model_evidence

    evidence = model_evidence(campaign, progress=progress)
    _say_what_is_missing(evidence, progress)
    if entry is not None:
        problem = evidence_cache.store(entry, evidence)
        if problem:
            progress(f"the drop-model evidence was not kept in the cache: {problem}")
    return assessment, evidence


def _say_what_is_missing(evidence, progress) -> None:
    """The model appendices a report will not have, or the stages not computed, said as
    the run goes (a CI log shows it without opening the report)."""
    if evidence.calibration is None:
        progress(f"no drop-model appendices: {evidence.note}")
    for failure in evidence.failures:
        progress(f"not computed: the {failure.stage} of {failure.gear} (its appendix says "
                 f"why and what to change)")


def report_campaign(campaign: Campaign, folder: str | Path, *, model: bool = True,
                    cache: bool = True, progress: Callable[[str], None] | None = None):
    """:func:`make_evidence`, then the report with its results and tables written into
    ``folder`` (all or nothing); returns the assessment and the model evidence."""
    assessment, evidence = make_evidence(campaign, model=model, cache=cache,
                                         progress=progress)
    render_report(assessment, folder, progress, evidence)
    return assessment, evidence
