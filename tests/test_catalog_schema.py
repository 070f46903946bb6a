"""The catalog's schema: created by the first addition, migrated by the next addition of a
later certkit, refused when a newer certkit made it; a catalog made by the first certkit
(SQLite, before the PostgreSQL backend) read and added to as it is.  On both backends
where the ``catalog`` fixture is taken (tests/conftest.py)."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

from certkit.archive.catalog import add, search
from certkit.cli import app

from .test_catalog import make_bag, rows

runner = CliRunner()


@pytest.fixture
def bags(tmp_path) -> dict[str, Path]:
    return {
        "A": make_bag(tmp_path / "a", "LSA-1", "Skylark LSA", ["2025-03-02", "2025-03-04"],
                      {"CFR23.725a/D1": "PASS", "F2245-drop-height/D1": "PASS"}),
        "B": make_bag(tmp_path / "b", "LSA-2", "Skylark LSA mod. B", ["2026-06-10"],
                      {"CFR23.725a/D1": "FAIL", "F2245-drop-height/D1": "PASS"}),
    }


V1_CATALOG = Path(__file__).parent / "data" / "catalog-v1.sqlite"


def test_a_catalog_made_by_the_first_certkit_is_read_and_added_to(bags, tmp_path):
    # tests/data/catalog-v1.sqlite was made by certkit before the PostgreSQL backend
    # (schema version 1 in PRAGMA user_version): two campaigns, bags no longer there
    import shutil

    catalog = tmp_path / "catalog.sqlite"
    shutil.copyfile(V1_CATALOG, catalog)
    assert [e.campaign_id for e in search(catalog)] == ["AMPH-1", "LSA-1"]
    assert add(catalog, bags["B"])[1] is True
    assert [e.campaign_id for e in search(catalog, aircraft="skylark")] == ["LSA-1", "LSA-2"]
    # still what the first certkit reads: version 1, no table but its own two
    assert rows(catalog, "PRAGMA user_version") == [(1,)]
    assert rows(catalog, "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name") \
        == [("campaigns",), ("verdicts",)]


def _version(catalog) -> int:
    if isinstance(catalog, Path):
        return rows(catalog, "PRAGMA user_version")[0][0]
    return rows(catalog, "SELECT schema_version FROM certkit_catalog")[0][0]


def test_an_older_catalog_is_migrated_by_the_next_addition(bags, catalog, monkeypatch):
    # a later certkit appends a step (here: an index); the catalog it finds at version 1
    # is migrated inside the addition's transaction
    from certkit.archive import catalog_rows

    add(catalog, bags["A"])
    assert _version(catalog) == 1
    step = ["CREATE INDEX IF NOT EXISTS verdicts_verdict ON verdicts (verdict)"]
    monkeypatch.setattr(catalog_rows, "MIGRATIONS", [*catalog_rows.MIGRATIONS, step])
    assert [e.campaign_id for e in search(catalog)] == ["LSA-1"]      # read as it is
    assert add(catalog, bags["B"])[1] is True
    assert _version(catalog) == 2
    index = "SELECT name FROM sqlite_master WHERE name = 'verdicts_verdict'" \
        if isinstance(catalog, Path) else \
        "SELECT indexname FROM pg_indexes WHERE indexname = 'verdicts_verdict'"
    assert rows(catalog, index) == [("verdicts_verdict",)]
    assert [e.campaign_id for e in search(catalog)] == ["LSA-1", "LSA-2"]


def test_a_catalog_of_a_newer_certkit_is_refused_not_changed(bags, catalog):
    add(catalog, bags["A"])
    rows(catalog, "PRAGMA user_version = 7" if isinstance(catalog, Path) else
         "UPDATE certkit_catalog SET schema_version = 7")
    for command in (["add", str(bags["B"])], ["list"]):
        result = runner.invoke(app, ["catalog", *command, "--catalog", str(catalog)])
        assert result.exit_code == 2, result.output
        assert "made by a newer certkit (schema version 7" in result.output
    assert _version(catalog) == 7 and rows(catalog, "SELECT count(*) FROM campaigns") == [(1,)]
