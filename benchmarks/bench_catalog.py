"""Concurrent additions to the archive catalog, on SQLite and on PostgreSQL.

Run:  .venv/bin/python benchmarks/bench_catalog.py [--processes 8] [--bags 50] [--runs 3]
                                                  [--postgresql URL] [--backends ...]

N processes (``--processes``) each add M bags of their own (``--bags``) to one new catalog
at the same moment, with ``certkit.archive.catalog.add`` (each bag verified, then indexed
in its own transaction), as N engineers of a lab adding at once would.  The bags are small
real ones (a results.json and bag-info.txt, as the catalog's tests make them), made once.
For each backend and run: the wall time from the start signal to the last addition, the
additions per second, and a check that all N x M landed, each once (the catalog's
entries, its distinct (bag hash, location) keys and its verdict rows).  The baseline
"verify only" is the same work without a database (the bags verified and described), to
show what the database adds.  Medians of ``--runs`` runs are quoted; the machine is shared
and noisy.

PostgreSQL: ``--postgresql`` is an administrator's URL (a database is created for each run
and dropped after); without it a throwaway server is started with .ci/postgresql (durable:
fsync on) and stopped at the end.  SQLite: a new file in a temporary folder on the local
disk, with certkit's settings (rollback journal, full synchronous writes).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
import uuid
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from certkit.archive.bag import write_bag  # noqa: E402

WORKER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from certkit.archive.catalog import add, describe
    catalog, go, *bags = sys.argv[1:]
    print("ready", flush=True)
    while not Path(go).exists():
        time.sleep(0.002)
    for bag in bags:
        if catalog == "-":
            describe(bag)
        else:
            assert add(catalog, bag)[1], bag
    print(time.monotonic(), flush=True)
""")


def make_bags(folder: Path, processes: int, bags: int) -> list[list[Path]]:
    """processes x bags small bags, each with two verdicts and its own campaign id."""
    made = []
    for worker in range(processes):
        mine = []
        for number in range(bags):
            bag = folder / f"w{worker:02d}" / f"bag{number:03d}"
            verdicts = {"CFR23.725a/D1": "PASS", "F2245-drop-height/D1":
                        "FAIL" if number % 7 == 0 else "PASS"}
            results = {"format": "certkit-results/1",
                       "outcome": "COMPLIANCE SHOWN" if number % 7 else "COMPLIANCE NOT SHOWN",
                       "counts": {k: list(verdicts.values()).count(k)
                                  for k in ("PASS", "FAIL", "NOT SHOWN")},
                       "finding_counts": {"error": 0, "warning": 1, "info": 0},
                       "verdicts": [{"id": key, "clause": key.split("/")[0],
                                     "run": key.split("/")[1], "gear": None,
                                     "verdict": verdict} for key, verdict in verdicts.items()]}
            (bag / "data" / "results").mkdir(parents=True)
            (bag / "data" / "results" / "results.json").write_text(json.dumps(results))
            campaign = f"W{worker:02d}-{number:03d}"
            write_bag(bag, [("Campaign-Id", campaign), ("External-Description", campaign),
                            ("Aircraft-Model", f"Skylark {worker}"),
                            ("Report-Number", f"R-{campaign}"), ("Report-Revision", "A"),
                            ("Issue-Date", "2025-03-04"), ("Test-Date", "2025-03-02"),
                            ("Bag-Software-Agent", "certkit benchmark")])
            mine.append(bag)
        made.append(mine)
    return made


def one_run(catalog: str, work: list[list[Path]], folder: Path) -> float:
    """Wall time [s] of the processes' additions to ``catalog`` ("-": verify only)."""
    go = folder / f"go-{uuid.uuid4().hex}"
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(REPO), *filter(None, [os.environ.get("PYTHONPATH")])]))
    processes = [subprocess.Popen([sys.executable, "-c", WORKER, catalog, str(go),
                                   *map(str, bags)], stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True, env=environment)
                 for bags in work]
    for process in processes:
        line = process.stdout.readline().strip()
        assert line == "ready", process.stderr.read()
    start = time.monotonic()
    go.touch()
    ends = []
    for process in processes:
        out, error = process.communicate(timeout=1800)
        assert process.returncode == 0, error
        ends.append(float(out.strip()))
    return max(ends) - start


def counts(catalog: str) -> tuple[int, int, int]:
    """(entries, distinct (bag hash, location) keys, verdict rows) of the catalog."""
    queries = ("SELECT count(*) FROM campaigns",
               "SELECT count(*) FROM (SELECT DISTINCT bag_hash, location FROM campaigns) k",
               "SELECT count(*) FROM verdicts")
    if catalog.startswith("postgresql://"):
        import psycopg

        with psycopg.connect(catalog) as connection:
            return tuple(connection.execute(q).fetchone()[0] for q in queries)
    connection = sqlite3.connect(catalog)
    try:
        return tuple(connection.execute(q).fetchone()[0] for q in queries)
    finally:
        connection.close()


def postgresql_server(given: str | None, folder: Path):
    """(admin URL, server version, the folder of a server started here or None)."""
    url, started = given, None
    if url is None:
        started = Path(tempfile.mkdtemp(prefix="certkit-bench-pg-"))
        url = subprocess.run([str(REPO / ".ci" / "postgresql"), "start", str(started)],
                             check=True, capture_output=True, text=True).stdout.strip()
    import psycopg

    with psycopg.connect(url) as connection:
        version = connection.execute("SHOW server_version").fetchone()[0]
        fsync = connection.execute("SHOW fsync").fetchone()[0]
    return url, f"PostgreSQL {version} (fsync {fsync})", started


def admin(url: str, statement: str) -> None:
    import psycopg

    with psycopg.connect(url, autocommit=True) as connection:
        connection.execute(statement)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--processes", type=int, default=8)
    parser.add_argument("--bags", type=int, default=50, help="bags per process")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--postgresql", help="an administrator's postgresql:// URL (default: "
                                             "a throwaway server, .ci/postgresql)")
    parser.add_argument("--backends", default="verify-only,sqlite,postgresql")
    options = parser.parse_args()
    backends = options.backends.split(",")
    total = options.processes * options.bags
    with tempfile.TemporaryDirectory(prefix="certkit-bench-catalog-") as temporary:
        folder = Path(temporary)
        work = make_bags(folder / "bags", options.processes, options.bags)
        versions = [f"SQLite {sqlite3.sqlite_version}"]
        url = started = None
        if "postgresql" in backends:
            url, version, started = postgresql_server(options.postgresql, folder)
            versions.append(version)
        try:
            results = {}
            for backend in backends:
                times = []
                for run in range(options.runs):
                    if backend == "verify-only":
                        catalog = "-"
                    elif backend == "sqlite":
                        catalog = str(folder / f"catalog-{run}.sqlite")
                    else:
                        name = f"certkit_bench_{uuid.uuid4().hex[:12]}"
                        admin(url, f"CREATE DATABASE {name}")
                        catalog = url.rsplit("/", 1)[0] + "/" + name
                    wall = one_run(catalog, work, folder)
                    if catalog != "-":
                        found = counts(catalog)
                        assert found == (total, total, 2 * total), \
                            f"{backend}: {found} landed, expected {total} (and {2 * total} " \
                            f"verdicts)"
                    if backend == "postgresql":
                        admin(url, f"DROP DATABASE {name} WITH (FORCE)")
                    times.append(wall)
                    landed = "" if catalog == "-" else f", all {total} landed once"
                    print(f"{backend} run {run + 1}: {wall:.2f} s, {total / wall:.0f} "
                          f"additions/s{landed}", flush=True)
                results[backend] = times
        finally:
            if started is not None:
                subprocess.run([str(REPO / ".ci" / "postgresql"), "stop", str(started)],
                               check=False)
    print()
    print(f"{options.processes} processes x {options.bags} bags = {total} additions, "
          f"medians of {options.runs} runs; {os.cpu_count()} cores, {platform.platform()}, "
          f"Python {platform.python_version()}, {', '.join(versions)}; "
          f"{dt.date.today().isoformat()}")
    print("| backend | processes x bags | median wall time | additions/s |")
    print("| --- | --- | --- | --- |")
    for backend, times in results.items():
        median = statistics.median(times)
        print(f"| {backend} | {options.processes} x {options.bags} | {median:.2f} s "
              f"(runs {', '.join(f'{t:.2f}' for t in times)}) | {total / median:.0f} |")


if __name__ == "__main__":
    main()
