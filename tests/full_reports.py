"""The checks of a shipped example's full report, made by the command line as a user makes
it (the drop model's calibration, identification and gap diagnosis included).  Each
example's test module (test_full_report_*.py) runs them on its own report, so that the two
reports are made on two test workers at once:

* the same bytes (results.json, report.pdf, report.html, the tables) with two threads of
  every kind (OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, NUMBA_NUM_THREADS) and the model stages
  in the process, as with one thread and the stages in two worker processes;
* the compliance body first: page 1 names every reason a criterion is not PASS, the body
  (before the first appendix) fits in 22 pages, each appendix opens saying it is not
  compliance evidence;
* exit 0, every stage computed, nothing stranded at a page break.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from .conftest import SEED_FIGURES
from .test_rendering import stranded_rows

THREADS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")
#: Where the full reports made here keep their drop-model evidence for the slow checks on
#: the same machine (conftest.full_report): each report is made afresh here, then its cache
#: entry is copied there.  An entry's key hashes the inputs and the code, so an entry made
#: by another version of either is never taken.
SHARED_CACHE = Path(tempfile.gettempdir()) / f"certkit-tests-{os.getuid()}" / "evidence"


def _start(spec: Path, out: Path, threads: int, workers: int) -> subprocess.Popen:
    """``certkit report`` of ``spec`` into ``out`` with ``threads`` threads of every kind and
    ``workers`` processes for the model stages, its evidence made afresh (into a cache of
    its own, empty)."""
    environment = dict(os.environ, CERTKIT_CACHE=str(out.parent / f"cache-{out.name}"),
                       CERTKIT_WORKERS=str(workers),
                       **{name: str(threads) for name in THREADS})
    return subprocess.Popen([sys.executable, "-m", "certkit.cli", "report", str(spec), "-o",
                             str(out)], env=environment, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def made(spec: Path, root: Path) -> tuple[Path, Path, list]:
    """The example's full report made twice at once: two threads of every kind with the
    model stages in this process (numba's threads share the drops), and one thread with
    the stages in two worker processes.  Returns the two output folders and the two runs'
    (exit code, stdout, stderr)."""
    outs = [root / "two-threads", root / "two-processes"]
    running = [_start(spec, outs[0], threads=2, workers=1),
               _start(spec, outs[1], threads=1, workers=2)]
    finished = []
    for process in running:
        stdout, stderr = process.communicate(timeout=900)
        finished.append((process.returncode, stdout, stderr))
    SHARED_CACHE.mkdir(parents=True, exist_ok=True, mode=0o700)
    for entry in (root / "cache-two-processes").glob("*.pickle"):
        shutil.copyfile(entry, SHARED_CACHE / entry.name)
    return outs[0], outs[1], finished


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def test_the_full_report_is_written_with_exit_0(reports):
    one, two, finished = reports
    for code, stdout, stderr in finished:
        assert code == 0, stderr
        assert "Traceback" not in stderr and "internal error" not in stderr
        assert "wrote" in stdout
    for folder in (one, two):
        assert {"report.pdf", "report.html", "results.json"} <= {p.name for p in
                                                                folder.iterdir()}


def test_one_and_two_threads_give_the_same_bytes(reports):
    one, two, _ = reports
    first, second = _files(one), _files(two)
    assert sorted(first) == sorted(second)
    differ = [name for name in first if first[name] != second[name]]
    assert differ == [], f"differ with 1 and 2 threads: {differ}"


def _pages(pdf: Path) -> list[str]:
    import pypdfium2

    document = pypdfium2.PdfDocument(pdf)
    try:
        return [document[i].get_textpage().get_text_range() for i in range(len(document))]
    finally:
        document.close()


def test_page_one_names_why_each_criterion_is_not_shown(reports):
    one, _, _ = reports
    import json

    results = json.loads((one / "results.json").read_text(encoding="utf-8"))
    first = " ".join(_pages(one / "report.pdf")[0].split())
    held = [v for v in results["verdicts"] if v["verdict"] != "PASS"]
    assert held, "the examples both have criteria NOT SHOWN"
    for verdict in held:
        # the reason in words and what would show it, for every criterion held back
        assert " ".join(verdict["shortfall"].split()) in first, verdict["id"]
        assert " ".join(verdict["remedy"].split()) in first, verdict["id"]


def test_the_body_comes_first_and_each_appendix_says_it_is_not_compliance_evidence(reports):
    one, _, _ = reports
    pages = _pages(one / "report.pdf")
    contents = next(n for n, text in enumerate(pages) if "Contents" in text)
    starts = {letter: next(n + 1 for n, text in enumerate(pages) if n > contents
                           and f"Appendix {letter}." in text)
              for letter in "ABC"}
    assert starts["A"] < starts["B"] < starts["C"], starts
    body = starts["A"] - 1
    assert body <= 22, f"the body takes {body} pages"
    html = (one / "report.html").read_text(encoding="utf-8")
    assert html.count("This appendix is not compliance evidence: no verdict rests on it.") == 3
    # no stage failed on either example
    assert 'class="not-computed"' not in html


def test_no_heading_caption_or_single_row_is_stranded(reports):
    one, _, _ = reports
    assert stranded_rows((one / "report.html").read_text(encoding="utf-8")) == []


def test_published_figures_appear_only_where_the_campaign_declares_them(reports):
    # the appendices are where the seed paper's figures used to leak into other campaigns:
    # the seed example declares them (reference_results), the second example does not
    one, _, _ = reports
    html = (one / "report.html").read_text(encoding="utf-8")
    # figures are inline SVG: their path coordinates are digits that mean nothing here
    text = re.sub(r"<svg.*?</svg>", "", html, flags=re.S)
    declared = "SEED-AMPHIBIAN-DT" in html
    for figure in SEED_FIGURES:
        assert (figure in text) == declared, figure
    assert ("reference results" in html) == declared
    if not declared:
        assert "seed" not in html.lower()
    # both examples' records are synthetic, and drawn as such
    assert "synthetic record" in html and ">measured<" not in html
