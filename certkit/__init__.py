"""certkit: landing-gear drop-test campaigns turned into airworthiness evidence.

Library use (what the CLI does)::

    import certkit
    campaign = certkit.load_campaign("campaigns/seed-amphibian/campaign.yaml")
    assessment = certkit.assess(campaign)
    certkit.render_report(assessment, "out")
"""

__version__ = "0.1.0"

from certkit.compliance.assessment import Assessment  # noqa: E402
from certkit.compliance.engine import assess  # noqa: E402
from certkit.errors import CertkitInputError  # noqa: E402
from certkit.evidence.report import render_report  # noqa: E402
from certkit.spec.campaign import Campaign, load_campaign  # noqa: E402

__all__ = ["Assessment", "Campaign", "CertkitInputError", "assess", "load_campaign",
           "render_report", "__version__"]
