"""The second example's full report (imperial units, a 2 kHz logger, one gear unit, a
planning campaign): the checks of tests/full_reports.py."""

from __future__ import annotations

import pytest

from .conftest import REPO
from .full_reports import *  # noqa: F403 - the shared checks, run on this example's report
from .full_reports import made

SECOND = REPO / "campaigns" / "lsa-main-gear-rig" / "campaign.yaml"


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    return made(SECOND, tmp_path_factory.mktemp("second-full"))
