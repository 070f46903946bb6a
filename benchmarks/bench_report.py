"""The report's speed and memory, against their targets (TARGETS).

Run:  .venv/bin/python benchmarks/bench_report.py [--runs N] [--campaign PATH] [--skip-big]

Prints, for the example campaign (medians of ``--runs`` runs, each a fresh process, so
imports count as they do for a user; BLAS threads pinned to one):

* ``certkit report`` cold: the drop-model evidence made again (``--no-cache``);
* ``certkit report`` with the evidence cached (the presentation alone changed);
* ``certkit report --no-model``;
* the PDF rendering alone (WeasyPrint on the full report's HTML, in-process);
* ``certkit archive`` (it takes the evidence from the cache a report filled) and
  ``certkit verify --recompute`` (which never uses the cache);
* a 70 MB logger file (a copy of the second example's first drop at 20 kHz, held at
  rest to 70 MB of CSV): ``certkit report --no-model``'s report.html size and the peak
  resident memory of the process against the file's size.

The machine is shared and noisy: quote the medians.  The evidence cache of the runs is a
temporary folder, never the user's own.
"""

from __future__ import annotations

import blas_threads  # noqa: F401  first: pins the BLAS threads of the timed commands

# isort: split
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

REPO = Path(__file__).resolve().parent.parent
EXAMPLE = REPO / "campaigns" / "seed-amphibian" / "campaign.yaml"
SECOND = REPO / "campaigns" / "lsa-main-gear-rig" / "campaign.yaml"
#: Seconds on a quiet 2-core machine, the seed example: the full report with its evidence made
#: afresh and taken from the cache, the report without the drop model, the PDF alone.
TARGETS = {"cold": 20.0, "cached": 4.0, "no-model": 3.0, "pdf": 5.0}


def _certkit(*arguments: str, cache: Path) -> float:
    """Wall time of one certkit command in a fresh process [s]."""
    environment = dict(os.environ, CERTKIT_CACHE=str(cache))
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "certkit.cli", *arguments], check=True,
                   capture_output=True, env=environment)
    return time.perf_counter() - start


def _summary(label: str, times: list[float], target: float | None = None) -> float:
    median = statistics.median(times)
    goal = f" (target <= {target:g} s: {'met' if median <= target else 'NOT met'})" \
        if target else ""
    print(f"{label}: median {median:.2f} s, min {min(times):.2f} s, max {max(times):.2f} s "
          f"over {len(times)} runs{goal}", flush=True)
    return median


def _pdf_alone(spec: Path, cache: Path, runs: int) -> list[float]:
    """WeasyPrint alone on the full report's HTML (the evidence from ``cache``)."""
    os.environ["CERTKIT_CACHE"] = str(cache)
    from certkit import load_campaign
    from certkit.evidence.pipeline import make_evidence
    from certkit.evidence.provenance import provenance
    from certkit.evidence.render import render_html, render_pdf
    from certkit.evidence.results_document import results_json
    from certkit.evidence.view import build_view

    campaign = load_campaign(spec)
    assessment, evidence = make_evidence(campaign)
    record = provenance(campaign.inputs)
    html = render_html(build_view(assessment, record, evidence))
    attachments = [(f"inputs/{item.name}", item.path.read_bytes(), "Source")
                   for item in campaign.inputs]
    attachments.append(("results.json", results_json(assessment, evidence, record), "Data"))
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        render_pdf(html, attachments, campaign.spec.document.date)
        times.append(time.perf_counter() - start)
    return times


def big_campaign(folder: Path, megabytes: float = 70.0, rate: float = 20_000.0) -> Path:
    """The second example with one drop, its record resampled to ``rate`` and held at rest
    until the CSV is ``megabytes`` MB: a long record from a fast logger."""
    spec = yaml.safe_load(SECOND.read_text(encoding="utf-8"))
    run = spec["runs"][0]
    spec["runs"] = [run]
    spec["instrumentation"]["sampling_rate"] = f"{rate:g} Hz"
    source = np.genfromtxt(SECOND.parent / run["data"]["file"], delimiter=",", names=True)
    names = source.dtype.names
    step_ms = 1e3 / rate
    header = ",".join(names) + "\n"
    target = megabytes * 1e6
    data = folder / "data"
    data.mkdir(parents=True)
    path = data / "big.csv"
    rng = np.random.default_rng(15)
    with path.open("w", encoding="utf-8") as handle:
        handle.write(header)
        t_end = float(source["time_ms"][-1])
        grid = np.arange(0.0, t_end, step_ms)
        columns = [np.interp(grid, source["time_ms"], source[name]) for name in names]
        columns[0] = grid
        written = len(header)
        block = 0
        while written < target:
            rows = np.column_stack(columns)
            if block:   # at rest after the record: its last values, with logger noise
                rows[:, 1:] = rows[-1:, 1:] + rng.normal(0.0, 1e-3, rows[:, 1:].shape)
                rows[:, 0] = grid + block * grid.size * step_ms
            text = "\n".join(",".join(f"{v:.4f}" for v in row) for row in rows) + "\n"
            handle.write(text)
            written += len(text)
            block += 1
    run["data"]["file"] = "data/big.csv"
    run["id"] = "D06"
    out = folder / "campaign.yaml"
    out.write_text(yaml.safe_dump(spec, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return out


#: Runs certkit's command line in this process and prints its peak resident memory [kB].
_PEAK = ("import resource, runpy, sys\n"
         "sys.argv = ['certkit'] + sys.argv[1:]\n"
         "try:\n    runpy.run_module('certkit.cli', run_name='__main__')\n"
         "finally:\n    print('peak-kB', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,"
         " file=sys.stderr)\n")


def _peak(*arguments: str, cache: Path) -> tuple[float, int]:
    """Wall time [s] and peak resident memory [bytes] of one certkit command."""
    environment = dict(os.environ, CERTKIT_CACHE=str(cache))
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", _PEAK, *arguments], check=True,
                          capture_output=True, env=environment, text=True)
    seconds = time.perf_counter() - start
    line = next(t for t in done.stderr.splitlines() if t.startswith("peak-kB"))
    return seconds, int(line.split()[1]) * 1024        # ru_maxrss is in kB on Linux


def _big(folder: Path, cache: Path) -> None:
    spec = big_campaign(folder / "big")
    size = (spec.parent / "data" / "big.csv").stat().st_size
    _, floor = _peak("report", str(EXAMPLE), "-o", str(folder / "floor-out"), "--no-model",
                     cache=cache)
    seconds, peak = _peak("report", str(spec), "-o", str(folder / "big-out"), "--no-model",
                          cache=cache)
    html = (folder / "big-out" / "report.html").stat().st_size
    pdf = (folder / "big-out" / "report.pdf").stat().st_size
    print(f"logger file of {size / 1e6:.1f} MB (20 kHz): report --no-model {seconds:.1f} s; "
          f"report.html {html / 1e6:.2f} MB (target <= 5 MB: "
          f"{'met' if html <= 5e6 else 'NOT met'}); report.pdf {pdf / 1e6:.1f} MB (the "
          f"logger file is attached); peak memory {peak / 1e6:.0f} MB = {peak / size:.1f} x "
          f"the file (target <= 4 x: {'met' if peak <= 4 * size else 'NOT met'}); the same "
          f"command on the example peaks at {floor / 1e6:.0f} MB, so the file costs "
          f"{(peak - floor) / 1e6:.0f} MB = {(peak - floor) / size:.1f} x its size",
          flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--campaign", type=Path, default=EXAMPLE)
    parser.add_argument("--skip-big", action="store_true",
                        help="leave out the 70 MB logger file")
    args = parser.parse_args()
    spec = str(args.campaign)
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        cache = folder / "cache"
        if not args.skip_big:
            _big(folder, cache)
        cold = [_certkit("report", spec, "-o", str(folder / f"cold{i}"), "--no-cache",
                         cache=cache) for i in range(args.runs)]
        report = _summary("certkit report, cold (evidence made again)", cold, TARGETS["cold"])
        _certkit("report", spec, "-o", str(folder / "fill"), cache=cache)   # fills the cache
        cached = [_certkit("report", spec, "-o", str(folder / f"warm{i}"), cache=cache)
                  for i in range(args.runs)]
        _summary("certkit report, evidence cached", cached, TARGETS["cached"])
        _summary("certkit report --no-model",
                 [_certkit("report", spec, "-o", str(folder / f"bare{i}"), "--no-model",
                           cache=cache) for i in range(args.runs)], TARGETS["no-model"])
        _summary("PDF rendering alone (full report, in-process)",
                 _pdf_alone(Path(spec), cache, args.runs), TARGETS["pdf"])
        archive = [_certkit("archive", spec, "-o", str(folder / f"bag{i}"), cache=cache)
                   for i in range(args.runs)]
        median = _summary("certkit archive (evidence cached)", archive)
        print(f"  = {median / report:.2f} x the cold report (target <= 1.5 x)")
        verify = [_certkit("verify", str(folder / "bag0"), "--recompute", cache=cache)
                  for _ in range(args.runs)]
        median = _summary("certkit verify --recompute (evidence made again)", verify)
        print(f"  = {median / report:.2f} x the cold report (target <= 1.5 x)")


if __name__ == "__main__":
    main()
