"""The checks of a shipped example's full report, made by the command line as a user makes
it (the drop model's calibration, identification and gap diagnosis included).  Each
example's test module (test_full_report_*.py) runs them on its own report: the second
example's in make test, the seed's (a minute of one core) among the slow checks, on the
report they share (conftest.full_report_run, made once per test session: :func:`made_once`);
tests/test_thread_counts.py, slow, checks that two threads and two processes give the same
bytes:

* the compliance body first: page 1 names every reason a criterion is not PASS, the body
  (before the first appendix) fits in 22 pages, each appendix opens saying it is not
  compliance evidence;
* exit 0, every stage computed (nothing stranded at a page break: tests/test_thread_counts.py).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from .conftest import SEED_FIGURES

THREADS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")
#: Where the full reports made here keep their drop-model evidence for the slow checks on
#: the same machine (conftest.full_report): each report is made afresh here, then its cache
#: entry is copied there.  An entry's key hashes the inputs and the code, so an entry made
#: by another version of either is never taken.
SHARED_CACHE = Path(tempfile.gettempdir()) / f"certkit-tests-{os.getuid()}" / "evidence"


def run_report(spec: Path, out: Path, threads: int, workers: int, cache: Path,
               *options: str) -> tuple[int, str, str]:
    """``certkit report`` of ``spec`` into ``out`` in a fresh process with ``threads``
    threads of every kind and ``workers`` processes for the model stages, its evidence cache
    in ``cache``: (exit code, stdout, stderr)."""
    environment = dict(os.environ, CERTKIT_CACHE=str(cache), CERTKIT_WORKERS=str(workers),
                       **{name: str(threads) for name in THREADS})
    done = subprocess.run([sys.executable, "-m", "certkit.cli", "report", str(spec), "-o",
                           str(out), *options], env=environment, text=True,
                          capture_output=True, timeout=900)
    return done.returncode, done.stdout, done.stderr


def made(spec: Path, root: Path) -> tuple[Path, tuple[int, str, str]]:
    """The example's full report with one thread and the model stages in the process (the
    test run's other worker keeps the other core busy), its evidence made afresh and then
    kept in :data:`SHARED_CACHE`.  Returns the output folder and the run's (exit code,
    stdout, stderr)."""
    out, cache = root / "out", root / "cache"
    finished = run_report(spec, out, 1, 1, cache)
    SHARED_CACHE.mkdir(parents=True, exist_ok=True, mode=0o700)
    for entry in cache.glob("*.pickle"):
        shutil.copyfile(entry, SHARED_CACHE / entry.name)
    return out, finished


def made_once(spec: Path, tmp_path_factory, name: str) -> tuple[Path, tuple[int, str, str]]:
    """:func:`made`, once per test session however many pytest-xdist workers ask for it:
    the first makes it in a folder ``name`` of the session's temporary folder (the parent
    of every worker's, as pytest-xdist documents), holding a lock beside it, and keeps the
    run's exit code and output there; the others wait for the lock and take the folder.
    Without xdist, the report is made in this session's own temporary folder.  The checks
    that take it only read it: one that writes there must copy it first."""
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        return made(spec, tmp_path_factory.mktemp(name))
    import fcntl

    session = tmp_path_factory.getbasetemp().parent
    root, record = session / name, session / f"{name}.json"
    with open(session / f"{name}.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)   # released when the file is closed
        if not record.is_file():
            # a worker that failed while making it (made raised) left no record: again
            shutil.rmtree(root, ignore_errors=True)
            root.mkdir(mode=0o700)
            _, (code, stdout, stderr) = made(spec, root)
            written = record.with_suffix(".partial")
            written.write_text(json.dumps({"code": code, "stdout": stdout, "stderr": stderr}),
                               encoding="utf-8")
            written.replace(record)
        run = json.loads(record.read_text(encoding="utf-8"))
    return root / "out", (run["code"], run["stdout"], run["stderr"])


def files(folder: Path) -> dict[str, bytes]:
    """Every file of an output folder, by its path in it."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def test_the_full_report_is_written_with_exit_0(reports):
    out, (code, stdout, stderr) = reports
    assert code == 0, stderr
    assert "Traceback" not in stderr and "internal error" not in stderr
    assert "wrote" in stdout
    assert {"report.pdf", "report.html", "results.json"} <= {p.name for p in out.iterdir()}


def _pages(pdf: Path) -> list[str]:
    import pypdfium2

    document = pypdfium2.PdfDocument(pdf)
    try:
        return [document[i].get_textpage().get_text_range() for i in range(len(document))]
    finally:
        document.close()


def test_page_one_names_why_each_criterion_is_not_shown(reports):
    one, _ = reports
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
    one, _ = reports
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


def test_published_figures_appear_only_where_the_campaign_declares_them(reports):
    # the appendices are where the seed paper's figures used to leak into other campaigns:
    # the seed example declares them (reference_results), the second example does not
    one, _ = reports
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
