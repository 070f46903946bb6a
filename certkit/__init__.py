"""certkit: landing-gear drop-test campaigns turned into airworthiness evidence.

Library use (what the CLI does)::

    import certkit
    campaign = certkit.load_campaign("campaigns/seed-amphibian/campaign.yaml")
    assessment = certkit.assess(campaign)
    certkit.render_report(assessment, "out")
"""

from certkit.compliance.assessment import Assessment
from certkit.compliance.engine import assess
from certkit.errors import CertkitInputError
from certkit.evidence.report import render_report
from certkit.spec.campaign import Campaign, load_campaign
from certkit.version import VERSION as __version__

__all__ = ["Assessment", "Campaign", "CertkitInputError", "assess", "load_campaign",
           "render_report", "__version__"]
