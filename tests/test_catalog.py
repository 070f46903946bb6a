"""`certkit catalog`: an index of archived campaigns, searched by aircraft, date and
verdict; a bag is indexed only when intact; concurrent additions all land.  Every test
taking the ``catalog`` fixture runs on both backends: an SQLite file and a database of its
own on a PostgreSQL server (tests/conftest.py; skipped without one, except in CI)."""

import json
import sqlite3
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from certkit.archive.campaign_bag import archive_campaign
from certkit.archive.bag import read_info, write_bag
from certkit.archive.catalog import add, search
from certkit.cli import app

from .conftest import SEED

runner = CliRunner()


def rows(catalog, query: str) -> list[tuple]:
    """What ``query`` reads from the catalog, on either backend."""
    if isinstance(catalog, Path):
        connection = sqlite3.connect(catalog)
        try:
            return connection.execute(query).fetchall()
        finally:
            connection.close()
    import psycopg

    with psycopg.connect(catalog) as connection:
        cursor = connection.execute(query)
        return [tuple(row) for row in cursor.fetchall()] if cursor.description else []


def make_bag(folder: Path, campaign: str, aircraft: str, tested: list[str],
             verdicts: dict[str, str]) -> Path:
    """A small bag with the labels and results an archive carries (no report)."""
    results = {
        "format": "certkit-results/1",
        "outcome": "COMPLIANCE SHOWN" if set(verdicts.values()) == {"PASS"} else
        "COMPLIANCE NOT SHOWN",
        "counts": {k: list(verdicts.values()).count(k) for k in ("PASS", "FAIL", "NOT SHOWN")},
        "finding_counts": {"error": 0, "warning": 1, "info": 0},
        "verdicts": [{"id": key, "clause": key.split("/")[0].replace("-", " "),
                      "run": key.split("/")[1], "gear": None, "verdict": verdict}
                     for key, verdict in verdicts.items()],
    }
    (folder / "data" / "results").mkdir(parents=True)
    (folder / "data" / "results" / "results.json").write_text(json.dumps(results))
    write_bag(folder, [("Campaign-Id", campaign), ("External-Description", f"{campaign} drops"),
                       ("Aircraft-Model", aircraft), ("Report-Number", f"R-{campaign}"),
                       ("Report-Revision", "A"), ("Issue-Date", tested[-1]),
                       *(("Test-Date", day) for day in tested),
                       ("Bag-Software-Agent", "certkit test")])
    return folder


@pytest.fixture
def bags(tmp_path) -> dict[str, Path]:
    return {
        "A": make_bag(tmp_path / "a", "LSA-1", "Skylark LSA", ["2025-03-02", "2025-03-04"],
                      {"CFR23.725a/D1": "PASS", "F2245-drop-height/D1": "PASS"}),
        "B": make_bag(tmp_path / "b", "LSA-2", "Skylark LSA mod. B", ["2026-06-10"],
                      {"CFR23.725a/D1": "FAIL", "F2245-drop-height/D1": "PASS"}),
        "C": make_bag(tmp_path / "c", "AMPH-1", "Heron amphibian", ["2024-01-10"],
                      {"CFR23.725a/D1": "NOT SHOWN"}),
    }


@pytest.mark.slow   # several reports or archives in real processes: CI runs it
def test_an_archived_campaign_is_indexed_from_its_bag(tmp_path, catalog):
    bag = tmp_path / "seed-bag"
    archive_campaign(SEED, bag, model=False)
    result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", str(catalog)])
    assert result.exit_code == 0, result.output
    assert result.output.startswith("added: SEED-AMPHIBIAN-DT")
    [entry] = search(catalog)
    # campaign.yaml: aircraft.model, document.*; README: 4 of 12 criteria pass, 8 not shown,
    # 2 data-quality errors
    assert entry.aircraft == "Light amphibious airplane (seed paper)"
    assert (entry.campaign_id, entry.report_number, entry.revision, entry.issue_date,
            entry.first_test_date, entry.last_test_date) == \
        ("SEED-AMPHIBIAN-DT", "CK-SEED-0001", "A", "2024-01-15", "2024-01-10", "2024-01-10")
    assert (entry.passed, entry.failed, entry.not_shown, entry.dq_errors) == (4, 0, 9, 2)
    assert entry.outcome == "COMPLIANCE NOT SHOWN"
    assert entry.location == str(bag.resolve())
    import hashlib
    assert entry.bag_hash == hashlib.sha256((bag / "tagmanifest-sha256.txt").read_bytes()) \
        .hexdigest()
    clauses = rows(catalog, "SELECT id, verdict FROM verdicts ORDER BY id")
    assert len(clauses) == 13 and ("CFR23.725a-limit-drop-height/D300", "PASS") in clauses


def test_adding_the_same_bag_twice_keeps_one_entry_and_a_copy_is_another(bags, tmp_path,
                                                                          catalog):
    assert add(catalog, bags["A"])[1] is True
    assert add(catalog, bags["A"])[1] is False
    result = runner.invoke(app, ["catalog", "add", str(bags["A"]), "--catalog", str(catalog)])
    assert result.exit_code == 0 and result.output.startswith("already catalogued: LSA-1")
    import shutil
    shutil.copytree(bags["A"], tmp_path / "copy-of-a")
    add(catalog, tmp_path / "copy-of-a")
    entries = search(catalog)
    assert [e.location for e in entries] == [str(bags["A"].resolve()),
                                             str((tmp_path / "copy-of-a").resolve())]
    assert entries[0].bag_hash == entries[1].bag_hash


def test_search_by_aircraft_text_dates_outcome_and_verdict(bags, catalog):
    for bag in bags.values():
        add(catalog, bag)

    def ids(**filters):
        return [e.campaign_id for e in search(catalog, **filters)]

    assert ids() == ["AMPH-1", "LSA-1", "LSA-2"]            # by aircraft name
    assert ids(aircraft="skylark") == ["LSA-1", "LSA-2"]      # case-insensitive substring
    assert ids(text="heron") == ["AMPH-1"] and ids(text="R-LSA-2") == ["LSA-2"]
    assert ids(campaign="LSA") == ["LSA-1", "LSA-2"]
    # tested within a range: LSA-1 ran 2025-03-02..04, so it overlaps a range from 03-03
    assert ids(since="2025-03-03") == ["LSA-1", "LSA-2"]
    assert ids(since="2025-03-05") == ["LSA-2"]
    assert ids(until="2025-03-01") == ["AMPH-1"]
    assert ids(since="2025-01-01", until="2025-12-31") == ["LSA-1"]
    assert ids(outcome="compliance shown") == ["LSA-1"]
    assert ids(verdict="FAIL") == ["LSA-2"]
    assert ids(verdict="not shown") == ["AMPH-1"]
    assert ids(verdict="PASS", clause="F2245") == ["LSA-1", "LSA-2"]
    assert ids(verdict="FAIL", clause="F2245") == []
    assert ids(text="%") == [] and ids(text="_") == []   # LIKE's wildcards are literal
    assert ids(aircraft="Skylark", verdict="FAIL") == ["LSA-2"]


def test_counts_beyond_32_bits_are_indexed(bags, catalog):
    # PostgreSQL's INTEGER has 32 bits: the counts are BIGINT there, as SQLite's integers
    bag = _rewritten(bags["A"], _counts(2 ** 40))
    add(catalog, bag)
    assert [e.passed for e in search(catalog)] == [2 ** 40]


def test_search_on_the_command_line(bags, catalog):
    result = runner.invoke(app, ["catalog", "add", *map(str, bags.values()), "--catalog",
                                 str(catalog)])
    assert result.exit_code == 0 and result.output.count("added: ") == 3
    result = runner.invoke(app, ["catalog", "search", "--aircraft", "skylark", "--verdict",
                                 "fail", "--json", "--catalog", str(catalog)])
    assert result.exit_code == 0
    assert [e["campaign_id"] for e in json.loads(result.output)] == ["LSA-2"]
    result = runner.invoke(app, ["catalog", "list", "--catalog", str(catalog)])
    assert result.output.startswith("3 archived campaign(s)")
    assert "report R-LSA-1 rev. A, issued 2025-03-04, tested 2025-03-02 to 2025-03-04" \
        in result.output
    result = runner.invoke(app, ["catalog", "search", "--from", "2025-13-01", "--catalog",
                                 str(catalog)])
    assert result.exit_code == 2 and "--from: expected a date as YYYY-MM-DD" in result.output
    result = runner.invoke(app, ["catalog", "search", "--verdict", "maybe", "--catalog",
                                 str(catalog)])
    assert result.exit_code == 2


def test_a_bag_changed_since_it_was_catalogued_is_refused_at_its_location(bags, catalog):
    from .test_archive import _rehash

    entry, _ = add(catalog, bags["B"])
    results = bags["B"] / "data" / "results" / "results.json"
    results.write_text(results.read_text().replace('"COMPLIANCE NOT SHOWN"',
                                                   '"COMPLIANCE SHOWN"'))
    _rehash(bags["B"])
    result = runner.invoke(app, ["catalog", "add", str(bags["B"]), "--catalog", str(catalog)])
    assert result.exit_code == 1, result.output
    assert f"the catalog holds another bag at {entry.location} (hash {entry.bag_hash}" \
        in result.output
    assert [e.bag_hash for e in search(catalog)] == [entry.bag_hash]


def test_a_bag_that_is_not_intact_is_not_added(bags, catalog):
    add(catalog, bags["A"])
    (bags["B"] / "data" / "results" / "results.json").write_text("{}")
    result = runner.invoke(app, ["catalog", "add", str(bags["B"]), str(bags["C"]),
                                 "--catalog", str(catalog)])
    assert result.exit_code == 1
    assert "not added to the catalog: the bag is not intact" in result.output
    assert "modified: data/results/results.json" in result.output
    assert [e.campaign_id for e in search(catalog)] == ["AMPH-1", "LSA-1"]  # C still added


def _made(catalog) -> bool:
    """Whether anything of the catalog exists: its file, or a table in its database."""
    if isinstance(catalog, Path):
        return catalog.exists()
    return rows(catalog, "SELECT count(*) FROM pg_tables WHERE schemaname = 'public'") != [(0,)]


def test_listing_a_catalog_that_does_not_exist_creates_nothing(catalog):
    result = runner.invoke(app, ["catalog", "list", "--catalog", str(catalog)])
    assert result.exit_code == 0 and "no catalogued campaign matches" in result.output
    result = runner.invoke(app, ["catalog", "search", "LSA", "--catalog", str(catalog)])
    assert result.exit_code == 0 and "no catalogued campaign matches" in result.output
    assert not _made(catalog)
    # something else where the catalog should be: a text file, another program's table
    if isinstance(catalog, Path):
        catalog.write_text("not a database, just text that is long enough " * 40)
    else:
        rows(catalog, "CREATE TABLE campaigns (name TEXT)")
    result = runner.invoke(app, ["catalog", "list", "--catalog", str(catalog)])
    assert result.exit_code == 2 and "not a certkit catalog" in result.output


ADDER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from certkit.archive.catalog import add
    catalog, bag, go = sys.argv[1:4]
    print("ready", flush=True)
    while not Path(go).exists():
        time.sleep(0.005)
    add(catalog, bag)
    print("added", flush=True)
""")


def _start(script: Path, catalog, bag: Path, go: Path) -> subprocess.Popen:
    process = subprocess.Popen([sys.executable, str(script), str(catalog), str(bag), str(go)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stdout.readline().strip() == "ready", process.stderr.read()
    return process


def _finish(processes) -> None:
    for process in processes:
        out, error = process.communicate(timeout=120)
        assert process.returncode == 0 and out.strip() == "added", error


def test_two_concurrent_additions_to_a_new_catalog_both_land(bags, tmp_path, catalog):
    # both processes wait at the start line, then add at once, each creating the schema
    script, go = tmp_path / "adder.py", tmp_path / "go"
    script.write_text(ADDER)
    processes = [_start(script, catalog, bags[k], go) for k in ("A", "B")]
    go.touch()
    _finish(processes)
    assert sorted(e.campaign_id for e in search(catalog)) == ["LSA-1", "LSA-2"]


@pytest.mark.slow   # several reports or archives in real processes: CI runs it
def test_two_additions_blocked_by_a_writer_both_land_when_it_finishes(bags, tmp_path,
                                                                     catalog):
    script, go = tmp_path / "adder.py", tmp_path / "go"
    script.write_text(ADDER)
    add(catalog, bags["C"])
    if isinstance(catalog, Path):
        holder = sqlite3.connect(catalog, isolation_level=None)
        holder.execute("BEGIN IMMEDIATE")   # another writer holds the catalog
    else:
        import psycopg

        holder = psycopg.connect(catalog, autocommit=True)
        holder.execute("BEGIN")             # another writer holds its campaigns
        holder.execute("LOCK TABLE campaigns IN SHARE ROW EXCLUSIVE MODE")
    processes = [_start(script, catalog, bags[k], go) for k in ("A", "B")]
    go.touch()
    time.sleep(6.0)           # both wait on the lock, longer than SQLite's default 5 s
    assert all(p.poll() is None for p in processes)
    holder.execute("COMMIT")
    holder.close()
    _finish(processes)
    assert sorted(e.campaign_id for e in search(catalog)) == ["AMPH-1", "LSA-1", "LSA-2"]


# --------------------------------------------------------------------------- hostile bags
def _rewritten(bag: Path, change) -> Path:
    """The bag with its results.json replaced by ``change(document)`` (text, or a document
    written as JSON) and its manifests written again: intact by its own manifests, as a bag
    edited by someone who knows BagIt is."""
    path = bag / "data" / "results" / "results.json"
    content = change(json.loads(path.read_text(encoding="utf-8")))
    path.write_text(content if isinstance(content, str) else json.dumps(content),
                    encoding="utf-8")
    info = [(label, value) for label, values in read_info(bag).items() for value in values
            if label != "Payload-Oxum"]
    write_bag(bag, info)
    return bag


def _counts(value):
    def change(document):
        document["counts"]["PASS"] = value
        return document
    return change


def _verdict_run(document):
    document["verdicts"][0]["run"] = [1]
    return document


def _verdict_id(value):
    def change(document):
        document["verdicts"][0]["id"] = value
        return document
    return change


HOSTILE_RESULTS = {
    "nested 100,000 deep": (lambda d: "[" * 100_000 + "]" * 100_000, "nested too deeply"),
    "a 5,000-digit integer": (lambda d: '{"format": ' + "9" * 5000 + "}",
                              "an integer of 5000 digits"),
    "a count that is a mapping": (_counts({"a": 1}), "where the catalog indexes passed"),
    "a count that is NaN": (_counts(float("nan")), "where the catalog indexes passed"),
    "a count beyond SQLite": (_counts(2 ** 64), "where the catalog indexes passed"),
    "a verdict's run that is a list": (_verdict_run, "verdicts[].run: expected text"),
    # text neither database stores: PostgreSQL refuses a NUL, UTF-8 a lone surrogate
    "a NUL in a verdict's id": (_verdict_id("D1\0"), "verdicts[].id: expected text"),
    "a lone surrogate in a verdict's id": (_verdict_id("D1\ud800"),
                                           "verdicts[].id: expected text"),
}


@pytest.mark.parametrize("name", HOSTILE_RESULTS)
def test_a_hostile_results_file_in_an_intact_bag_is_refused_naming_it(bags, catalog, name):
    # before: RecursionError and OverflowError were "a certkit bug" (exit 3), a mapping was
    # blamed on --catalog, and a NaN count was silently not added ("already catalogued")
    change, words = HOSTILE_RESULTS[name]
    bag = _rewritten(bags["A"], change)
    result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", str(catalog)])
    assert result.exit_code == 2, (result.output, result.exception)
    assert str(bag) in result.output and words in result.output, result.output
    assert "--catalog" not in result.output and "certkit bug" not in result.output
    assert search(catalog) == []


@pytest.mark.parametrize("name", ["nested 100,000 deep", "a 5,000-digit integer"])
def test_a_results_file_json_cannot_hold_is_refused_by_verify_recompute(bags, name):
    change, words = HOSTILE_RESULTS[name]
    bag = _rewritten(bags["A"], change)
    result = runner.invoke(app, ["verify", "--recompute", str(bag)])
    assert result.exit_code == 2, (result.output, result.exception)
    assert f"{bag}: data/results/results.json: " in result.output and words in result.output


def test_a_catalog_path_through_a_file_or_at_a_folder_is_an_input_error(bags, tmp_path):
    # before: a file where the catalog's folder must be said only "File exists", and a
    # folder named as the catalog "not a certkit catalog (unable to open database file)"
    (tmp_path / "notes").write_text("a file", encoding="utf-8")
    for catalog, words in ((tmp_path / "notes" / "catalog.sqlite", "a file stands where a "
                                                                   "folder must be"),
                           (tmp_path, "it is a folder")):
        result = runner.invoke(app, ["catalog", "add", str(bags["A"]), "--catalog",
                                     str(catalog)])
        assert result.exit_code == 2, (result.output, result.exception)
        assert str(catalog) in result.output and words in result.output, result.output


# ------------------------------------------------------------------ a failed addition
def test_a_failed_addition_keeps_a_new_catalog_another_process_filled(bags, tmp_path,
                                                                     monkeypatch):
    # this call found no catalog; while it waited, another process created it and added
    # its campaign; this call then fails: the other's catalog must stay
    import certkit.archive.catalog as catalog_module

    catalog = tmp_path / "new.sqlite"
    real_insert = catalog_module._insert

    def other_process_first(path, entry, verdicts, bag):
        real_insert(path, *catalog_module.describe(bags["C"]), bags["C"])
        raise sqlite3.OperationalError("database is locked")

    monkeypatch.setattr(catalog_module, "_insert", other_process_first)
    with pytest.raises(sqlite3.OperationalError):
        add(catalog, bags["A"])
    assert [e.campaign_id for e in search(catalog)] == ["AMPH-1"]


def test_a_failed_addition_keeps_a_new_catalog_another_process_is_writing(bags, tmp_path,
                                                                         monkeypatch):
    import certkit.archive.catalog as catalog_module

    catalog = tmp_path / "new.sqlite"
    others = []

    def locked_out(path, entry, verdicts, bag):
        # after this call found no catalog, the other process creates it and writes
        holder = sqlite3.connect(path, isolation_level=None)
        holder.execute("BEGIN IMMEDIATE")
        holder.execute("CREATE TABLE campaigns (bag_hash TEXT)")
        others.append(holder)
        raise sqlite3.OperationalError("database is locked")

    monkeypatch.setattr(catalog_module, "_insert", locked_out)
    with pytest.raises(sqlite3.OperationalError):
        add(catalog, bags["A"])
    assert catalog.exists() and catalog.with_name("new.sqlite-journal").exists()
    others[0].execute("COMMIT")                     # its transaction still completes
    others[0].close()
    assert sqlite3.connect(catalog).execute("SELECT count(*) FROM sqlite_master WHERE name = "
                                            "'campaigns'").fetchone()[0] == 1


def test_a_failed_addition_removes_the_empty_catalog_it_created(bags, tmp_path, monkeypatch):
    import certkit.archive.catalog as catalog_module

    catalog = tmp_path / "sub" / "new.sqlite"

    def fails_after_creating(path, entry, verdicts, bag):
        path.parent.mkdir(parents=True, exist_ok=True)
        sqlite3.connect(path).execute("CREATE TABLE campaigns (bag_hash TEXT)").connection \
            .close()
        raise sqlite3.OperationalError("disk I/O error")

    monkeypatch.setattr(catalog_module, "_insert", fails_after_creating)
    with pytest.raises(sqlite3.OperationalError):
        add(catalog, bags["A"])
    assert not (tmp_path / "sub").exists()


# ------------------------------------------------------------------ concurrent additions
def _store(catalog, entry, verdicts) -> bool:
    """The addition of rows already described, on either backend (no verification)."""
    import certkit.archive.catalog as catalog_module

    if isinstance(catalog, Path):
        return catalog_module._insert(catalog, entry, verdicts, entry.location)
    from certkit.archive import catalog_postgresql

    return catalog_postgresql.insert(catalog, entry, verdicts, entry.location)


def test_two_bags_added_at_one_location_at_once_one_lands_the_other_is_refused(bags, catalog):
    # the check "another bag at this location?" and the insertion are one decision: two
    # additions racing at one location never both land (the bag changed between them)
    import dataclasses
    import threading

    from certkit.archive.catalog import CatalogRefusal, describe

    entry, verdicts = describe(bags["A"])
    _store(catalog, *describe(bags["B"]))           # the schema exists: only the race
    for round_ in range(8):
        location = f"/lab/bags/{round_}"
        first = dataclasses.replace(entry, location=location)
        second = dataclasses.replace(first, bag_hash="f" * 64)
        start, outcomes = threading.Barrier(2), []

        def add_at_once(rows):
            start.wait()
            try:
                outcomes.append(_store(catalog, rows, verdicts))
            except CatalogRefusal as refusal:
                outcomes.append(str(refusal))

        threads = [threading.Thread(target=add_at_once, args=(rows,))
                   for rows in (first, second)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(timeout=120)
        assert sum(outcome is True for outcome in outcomes) == 1, outcomes
        assert any("the catalog holds another bag at" in str(o) for o in outcomes), outcomes
        assert len([e for e in search(catalog) if e.location == location]) == 1


MANY_ADDER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from certkit.archive.catalog import add
    catalog, go, *bags = sys.argv[1:]
    print("ready", flush=True)
    while not Path(go).exists():
        time.sleep(0.005)
    for bag in bags:
        add(catalog, bag)
    print("added", flush=True)
""")


@pytest.mark.slow   # several processes adding 11 bags each
def test_four_processes_adding_at_once_all_land_once(tmp_path, catalog):
    # each adds 10 bags of its own and one bag all of them add: 41 entries, none twice
    shared = make_bag(tmp_path / "shared", "SHARED", "Heron amphibian", ["2024-02-01"],
                      {"CFR23.725a/D1": "PASS"})
    script, go = tmp_path / "adder.py", tmp_path / "go"
    script.write_text(MANY_ADDER)
    processes = []
    for worker in range(4):
        own = [make_bag(tmp_path / f"w{worker}-{n}", f"W{worker}-{n:02d}", "Skylark LSA",
                        ["2025-03-02"], {"CFR23.725a/D1": "PASS"}) for n in range(10)]
        processes.append(subprocess.Popen(
            [sys.executable, str(script), str(catalog), str(go), str(shared), *map(str, own)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True))
    for process in processes:
        assert process.stdout.readline().strip() == "ready", process.stderr.read()
    go.touch()
    _finish(processes)
    entries = search(catalog)
    assert len(entries) == 41
    assert len({(e.bag_hash, e.location) for e in entries}) == 41
    assert sorted(e.campaign_id for e in entries)[:2] == ["SHARED", "W0-00"]
    assert rows(catalog, "SELECT count(*) FROM verdicts") == [(41,)]


def test_eight_additions_creating_the_catalog_at_once_all_land(bags, tmp_path, catalog,
                                                               request):
    # each finds no schema and creates it: creating tables at once must not collide, nor
    # may one see another's catalog half made (8 rounds, each on a new catalog)
    import dataclasses
    import threading

    from certkit.archive.catalog import describe

    entry, verdicts = describe(bags["A"])
    for round_ in range(8):
        if isinstance(catalog, Path):
            fresh = tmp_path / f"catalog-{round_}.sqlite"
        else:
            from .conftest import admin_execute, database_url

            server = request.getfixturevalue("postgresql_server")
            name = f"{catalog.rpartition('/')[2]}_{round_}"
            admin_execute(server, f"CREATE DATABASE {name}")
            request.addfinalizer(lambda name=name: admin_execute(
                server, f"DROP DATABASE IF EXISTS {name} WITH (FORCE)"))
            fresh = database_url(server, name)
        start, outcomes = threading.Barrier(8), []

        def add_at_once(number):
            start.wait()
            try:
                outcomes.append(_store(fresh, dataclasses.replace(
                    entry, location=f"/lab/{number}"), verdicts))
            except Exception as error:     # noqa: BLE001 - reported by the assertion
                outcomes.append(error)

        threads = [threading.Thread(target=add_at_once, args=(n,)) for n in range(8)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(timeout=120)
        assert outcomes == [True] * 8, outcomes
        assert sorted(e.location for e in search(fresh)) == [f"/lab/{n}" for n in range(8)]
