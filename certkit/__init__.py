"""certkit: landing-gear drop-test campaigns turned into airworthiness evidence.

Library use (what the CLI does)::

    import certkit
    campaign = certkit.load_campaign("campaigns/seed-amphibian/campaign.yaml")
    assessment = certkit.assess(campaign)
    certkit.render_report(assessment, "out")
"""

import importlib

from certkit.version import VERSION as __version__

# Exported lazily (PEP 562), so that ``import certkit.cli`` runs the command line's first
# lines (its stop-signal handling) before the heavy modules load.
_EXPORTS = {"Assessment": "certkit.compliance.assessment", "assess": "certkit.compliance.engine",
            "CertkitInputError": "certkit.errors", "render_report": "certkit.evidence.report",
            "Campaign": "certkit.spec.campaign", "load_campaign": "certkit.spec.campaign"}
__all__ = ["Assessment", "Campaign", "CertkitInputError", "assess", "load_campaign",
           "render_report", "__version__"]


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'certkit' has no attribute {name!r}")
