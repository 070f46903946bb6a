"""The same inputs give the same bytes at any thread count: each shipped example's full
report made with one thread of every kind (OMP_NUM_THREADS, OPENBLAS_NUM_THREADS,
NUMBA_NUM_THREADS) and the model stages in the process is byte for byte the report made
with two threads and the stages in two worker processes; and nothing of it is stranded at a page
break.  Before, the second example's
calibration put the polytropic exponent on its bound with one BLAS thread and not with two,
and its full report failed on the one and not on the other.

Slow (two full reports each): the seed's one-thread report is the one the other slow checks
share (conftest.full_report_run: one thread, the stages in the process, evidence made
afresh, once per test session by whichever worker first needs it); the second example's
takes the evidence the fast test_full_report_second.py made on this machine when there is
one (CI runs it first); the two-thread reports make their own."""

from __future__ import annotations

import shutil

import pytest

from .conftest import REPO, SEED
from .full_reports import SHARED_CACHE, files, run_report
from .test_rendering import stranded_rows

SECOND = REPO / "campaigns" / "lsa-main-gear-rig" / "campaign.yaml"


@pytest.mark.slow
@pytest.mark.parametrize("spec", [SEED, SECOND], ids=["seed example", "second example"])
def test_one_thread_in_one_process_gives_the_bytes_of_two_threads_in_two(spec, tmp_path,
                                                                        request):
    # the two-thread report first: while another test worker makes the shared one-thread
    # report (conftest.full_report_run), this one does not wait for it idle
    two = run_report(spec, tmp_path / "two", 2, 2, tmp_path / "own", "--no-cache")
    if spec == SEED:
        one_folder, one = request.getfixturevalue("full_report_run")
    else:
        shared = tmp_path / "shared"
        shared.mkdir(mode=0o700)
        for entry in SHARED_CACHE.glob("*.pickle"):
            shutil.copyfile(entry, shared / entry.name)
        one_folder = tmp_path / "one"
        one = run_report(spec, one_folder, 1, 1, shared)
    for code, _, stderr in (one, two):
        assert code == 0, stderr
    # its evidence made afresh, in two worker processes
    assert "(2 processes)" in two[2] and "taken from the cache" not in two[2]
    first, second = files(one_folder), files(tmp_path / "two")
    assert sorted(first) == sorted(second)
    differ = [name for name in first if first[name] != second[name]]
    assert differ == [], f"differ with 1 and 2 threads: {differ}"
    # and a page break strands no heading, caption or single row of it
    assert stranded_rows((one_folder / "report.html").read_text(encoding="utf-8")) == []
