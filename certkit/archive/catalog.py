"""An SQLite index of archived campaigns, so that a lab finds every campaign of an
aircraft type, a date range or a failed clause without opening the bags.

A bag is catalogued only after it verifies intact; what is indexed comes from its
bag-info.txt and its archived results.json (a row per criterion).  A bag is keyed by its
hash (SHA-256 of its tag manifest) and its location, so the same bag added twice is one
entry and a copy elsewhere is another.  Each addition is one ``BEGIN IMMEDIATE``
transaction with a generous busy timeout: two processes adding at once both land.
"""

from __future__ import annotations

import contextlib
import errno
import os
import sqlite3
from dataclasses import asdict, dataclass
from pathlib import Path

from certkit.archive.bag import BagError, bag_hash, check_bag, read_info
from certkit.archive.campaign_bag import archived_results, opened_bag
from certkit.errors import CertkitInputError, EnvironmentFailure, shown
from certkit.outputs import writing_failure

SCHEMA_VERSION = 1
SCHEMA = """
CREATE TABLE IF NOT EXISTS campaigns (
    bag_hash        TEXT NOT NULL,
    location        TEXT NOT NULL,
    campaign_id     TEXT NOT NULL,
    title           TEXT NOT NULL,
    aircraft        TEXT NOT NULL,
    report_number   TEXT NOT NULL,
    revision        TEXT NOT NULL,
    issue_date      TEXT NOT NULL,
    first_test_date TEXT NOT NULL,
    last_test_date  TEXT NOT NULL,
    outcome         TEXT NOT NULL,
    passed          INTEGER NOT NULL,
    failed          INTEGER NOT NULL,
    not_shown       INTEGER NOT NULL,
    dq_errors       INTEGER NOT NULL,
    dq_warnings     INTEGER NOT NULL,
    software        TEXT NOT NULL,
    PRIMARY KEY (bag_hash, location)
);
CREATE TABLE IF NOT EXISTS verdicts (
    bag_hash  TEXT NOT NULL,
    id        TEXT NOT NULL,
    clause    TEXT NOT NULL,
    run       TEXT,
    gear      TEXT,
    verdict   TEXT NOT NULL,
    PRIMARY KEY (bag_hash, id)
);
CREATE INDEX IF NOT EXISTS campaigns_aircraft ON campaigns (aircraft);
"""
TIMEOUT_S = 60.0


class CatalogRefusal(Exception):
    """The bag was not added: it is not intact (the changes are listed), or the catalog
    holds another bag at its location (it changed since it was catalogued)."""

    def __init__(self, bag: Path, reason: str, changes=()):
        self.changes = list(changes)
        super().__init__(f"{bag}: not added to the catalog: {reason}")


@dataclass(frozen=True)
class Entry:
    bag_hash: str
    location: str
    campaign_id: str
    title: str
    aircraft: str
    report_number: str
    revision: str
    issue_date: str
    first_test_date: str
    last_test_date: str
    outcome: str
    passed: int
    failed: int
    not_shown: int
    dq_errors: int
    dq_warnings: int
    software: str

    def as_dict(self) -> dict:
        return asdict(self)


def _catalog_error(path: Path, message: str) -> CertkitInputError:
    return CertkitInputError.single(str(path), None, "--catalog", message)


# SQLite's primary result codes (sqlite3.Error.sqlite_errorcode & 0xff) for what the machine
# refuses, as the errno whose wording and remedy certkit.errors gives; SQLITE_READONLY and
# SQLITE_CANTOPEN depend on the disk (see _sqlite_failure)
_SQLITE_PERM, _SQLITE_BUSY, _SQLITE_LOCKED, _SQLITE_READONLY = 3, 5, 6, 8
_SQLITE_IOERR, _SQLITE_FULL, _SQLITE_CANTOPEN = 10, 13, 14
_SQLITE_ERRNO = {_SQLITE_PERM: errno.EPERM, _SQLITE_IOERR: errno.EIO,
                 _SQLITE_FULL: errno.ENOSPC}


def _sqlite_failure(path: Path, error: sqlite3.Error, doing: str) -> Exception:
    """The one mapping of an SQLite error on the catalog at ``path``: what the machine
    refuses (a full disk, a read-only file or disk, no permission, a failing disk, another
    process holding the catalog past the timeout) is an EnvironmentFailure (exit 4); a
    file that is not a certkit catalog (another database, a folder, damaged) is bad input
    (exit 2)."""
    code = (getattr(error, "sqlite_errorcode", None) or 0) & 0xFF
    if code in (_SQLITE_BUSY, _SQLITE_LOCKED):
        return EnvironmentFailure(path, f"{doing}: another process held it for {TIMEOUT_S:g} "
                                        f"s; try again when it has finished")
    number = _SQLITE_ERRNO.get(code)
    if code == _SQLITE_READONLY or (code == _SQLITE_CANTOPEN and not path.is_dir()):
        folder = path if path.is_dir() else path.parent
        read_only = os.statvfs(folder).f_flag & os.ST_RDONLY if folder.exists() else False
        number = errno.EROFS if read_only else errno.EACCES
    if number is not None:
        return EnvironmentFailure.from_os_error(OSError(number, str(error)), path, doing)
    if path.is_dir():
        return _catalog_error(path, f"{doing}: it is a folder; name the catalog's file")
    return _catalog_error(path, f"{doing}: not a certkit catalog (SQLite says: {error})")


def _connect(path: Path) -> sqlite3.Connection:
    try:
        connection = sqlite3.connect(path, timeout=TIMEOUT_S, isolation_level=None)
        version = connection.execute("PRAGMA user_version").fetchone()[0]
        tables = {row[0] for row in connection.execute(
            "SELECT name FROM sqlite_master WHERE type = 'table'")}
    except sqlite3.Error as error:
        raise _sqlite_failure(path, error, "cannot open the catalog") from None
    if version not in (0, SCHEMA_VERSION) or not tables <= {"campaigns", "verdicts"}:
        connection.close()
        found = f"schema version {version}" if version else f"tables {sorted(tables)}"
        raise _catalog_error(path, f"not a certkit catalog of version {SCHEMA_VERSION} "
                                   f"({found})")
    return connection


def _first(info: dict[str, list[str]], label: str) -> str:
    return (info.get(label) or [""])[0]


def describe(bag: str | Path) -> tuple[Entry, list[tuple]]:
    """The catalog entry and verdict rows of the bag at ``bag`` (a folder or a .zip).

    Raises CatalogRefusal when the bag is not intact, BagError when it is not a bag.
    """
    bag = Path(bag)
    with opened_bag(bag) as folder:
        changes = check_bag(folder)
        if changes:
            raise CatalogRefusal(bag, "the bag is not intact", changes)
        info = read_info(folder)
        _, results = archived_results(folder)
        digest = bag_hash(folder)
    dates = sorted(info.get("Test-Date", [])) or [""]
    try:
        counts, findings = results["counts"], results["finding_counts"]
        entry = Entry(
            bag_hash=digest, location=str(bag.resolve()),
            campaign_id=_first(info, "Campaign-Id"),
            title=_first(info, "External-Description"),
            aircraft=_first(info, "Aircraft-Model"),
            report_number=_first(info, "Report-Number"),
            revision=_first(info, "Report-Revision"), issue_date=_first(info, "Issue-Date"),
            first_test_date=dates[0], last_test_date=dates[-1], outcome=results["outcome"],
            passed=counts["PASS"], failed=counts["FAIL"], not_shown=counts["NOT SHOWN"],
            dq_errors=findings["error"], dq_warnings=findings["warning"],
            software=_first(info, "Bag-Software-Agent"))
        verdicts = [(digest, v["id"], v["clause"], v["run"], v["gear"], v["verdict"])
                    for v in results["verdicts"]]
    except (KeyError, TypeError) as error:
        raise BagError(f"{bag}: its results.json lacks what the catalog indexes "
                       f"({error})") from None
    _check_indexed(bag, entry, verdicts)
    return entry, verdicts


_COUNTS = {"passed", "failed", "not_shown", "dq_errors", "dq_warnings"}
_VERDICT_FIELDS = ("bag_hash", "id", "clause", "run", "gear", "verdict")


def _check_indexed(bag: Path, entry: Entry, verdicts: list[tuple]) -> None:
    """Raise BagError unless every value indexed is what its column holds: a count a
    whole number from 0 to 2^63 - 1 (SQLite's integers), anything else text (a verdict's run and
    gear may be null).  A results.json edited and re-hashed can hold anything."""
    def refuse(name: str, value: object, expected: str):
        raise BagError(f"{bag}: its results.json holds {shown(value)} where the catalog "
                       f"indexes {name}: expected {expected}")

    for name, value in entry.as_dict().items():
        if name in _COUNTS:
            if type(value) is not int or not 0 <= value < 2 ** 63:
                refuse(name, value, "a count (a whole number from 0)")
        elif not isinstance(value, str):
            refuse(name, value, "text")
    for row in verdicts:
        for name, value in zip(_VERDICT_FIELDS, row):
            if not isinstance(value, str) and not (name in ("run", "gear") and value is None):
                refuse(f"verdicts[].{name}", value, "text")


def add(catalog: str | Path, bag: str | Path) -> tuple[Entry, bool]:
    """Verify the bag and index it; (entry, False) when it was already catalogued.

    A catalog this call created is removed again (with the folders it made) when the
    addition fails, so a full or read-only disk leaves nothing behind."""
    catalog = Path(catalog)
    entry, verdicts = describe(bag)
    made = [folder for folder in [catalog.parent, *catalog.parent.parents]
            if not folder.exists()]
    new = not os.path.lexists(catalog)
    try:
        added = _insert(catalog, entry, verdicts, bag)
    except BaseException:
        if new and _unused(catalog):
            for leftover in (catalog, catalog.with_name(catalog.name + "-journal")):
                with contextlib.suppress(OSError):
                    leftover.unlink()
        for folder in made:
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise
    return entry, added


def _unused(catalog: Path) -> bool:
    """Whether a catalog this call set out to create may be removed after its failure: no
    other process is writing it (its write lock is free at once) and it holds no campaign.
    Two additions to a new catalog can run together; the one that fails must not take the
    other's entries, or its open transaction, with it."""
    if not os.path.lexists(catalog):
        return True
    try:
        probe = sqlite3.connect(catalog, timeout=0, isolation_level=None)
    except sqlite3.Error:
        return True
    try:
        probe.execute("BEGIN IMMEDIATE")
        tables = probe.execute("SELECT count(*) FROM sqlite_master WHERE name = "
                               "'campaigns'").fetchone()[0]
        rows = probe.execute("SELECT count(*) FROM campaigns").fetchone()[0] if tables else 0
        probe.execute("ROLLBACK")
    except sqlite3.OperationalError:       # locked by another writer
        return False
    except sqlite3.Error:                  # not (yet) a database: what this call left
        return True
    finally:
        probe.close()
    return rows == 0


def _insert(catalog: Path, entry: Entry, verdicts: list[tuple], bag: str | Path) -> bool:
    try:
        catalog.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise writing_failure(error, catalog, "cannot create its folder", key="--catalog") \
            from None
    connection = _connect(catalog)
    try:
        connection.execute("BEGIN IMMEDIATE")
        for statement in filter(str.strip, SCHEMA.split(";")):
            connection.execute(statement)   # (executescript would commit first)
        connection.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
        before = connection.execute(
            "SELECT bag_hash FROM campaigns WHERE location = ? AND bag_hash != ?",
            (entry.location, entry.bag_hash)).fetchone()
        if before is not None:
            connection.execute("ROLLBACK")
            raise CatalogRefusal(Path(bag), f"the catalog holds another bag at "
                                            f"{entry.location} (hash {before[0]}, now "
                                            f"{entry.bag_hash}): the bag was changed and "
                                            f"re-hashed since it was catalogued")
        fields = list(entry.as_dict())
        cursor = connection.execute(
            f"INSERT OR IGNORE INTO campaigns ({', '.join(fields)}) "
            f"VALUES ({', '.join('?' * len(fields))})", list(entry.as_dict().values()))
        added = cursor.rowcount == 1
        connection.executemany("INSERT OR IGNORE INTO verdicts VALUES (?, ?, ?, ?, ?, ?)",
                               verdicts)
        connection.execute("COMMIT")
    except sqlite3.Error as error:
        if connection.in_transaction:
            with contextlib.suppress(sqlite3.Error):
                connection.execute("ROLLBACK")
        raise _sqlite_failure(catalog, error, "cannot add to the catalog") from None
    finally:
        connection.close()
    return added


def search(catalog: str | Path, text: str | None = None, *, aircraft: str | None = None,
           campaign: str | None = None, outcome: str | None = None, since: str | None = None,
           until: str | None = None, verdict: str | None = None, clause: str | None = None
           ) -> list[Entry]:
    """Catalogued campaigns matching every filter given (none: all of them).

    ``text`` matches campaign id, title, aircraft or report number; ``aircraft``,
    ``campaign`` and ``clause`` are case-insensitive substrings; ``outcome`` is exact
    (case-insensitive); ``since``/``until`` (YYYY-MM-DD) keep campaigns tested within
    the range; ``verdict`` keeps campaigns with at least one criterion of that verdict
    (of a clause matching ``clause``, when given).
    """
    catalog = Path(catalog)
    if not catalog.exists():
        return []
    where, values = [], []

    def like(columns: tuple[str, ...], value: str) -> str:
        pattern = "%" + value.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_") + "%"
        values.extend([pattern] * len(columns))
        return "(" + " OR ".join(f"{c} LIKE ? ESCAPE '\\'" for c in columns) + ")"

    if text:
        where.append(like(("campaign_id", "title", "aircraft", "report_number"), text))
    if aircraft:
        where.append(like(("aircraft",), aircraft))
    if campaign:
        where.append(like(("campaign_id",), campaign))
    if outcome:
        where.append("upper(outcome) = upper(?)")
        values.append(outcome)
    if since:
        where.append("last_test_date >= ?")
        values.append(since)
    if until:
        where.append("first_test_date <= ?")
        values.append(until)
    if verdict or clause:
        inner = ["v.bag_hash = campaigns.bag_hash"]
        if verdict:
            inner.append("upper(v.verdict) = upper(?)")
            values.append(verdict)
        if clause:
            inner.append(like(("v.clause", "v.id"), clause))
        where.append(f"EXISTS (SELECT 1 FROM verdicts v WHERE {' AND '.join(inner)})")
    query = "SELECT * FROM campaigns" + (" WHERE " + " AND ".join(where) if where else "") + \
        " ORDER BY aircraft, campaign_id, issue_date, location"
    connection = _connect(catalog)
    try:
        rows = connection.execute(query, values).fetchall()
    except sqlite3.Error as error:
        if "no such table" in str(error):
            return []
        raise _sqlite_failure(catalog, error, "cannot read the catalog") from None
    finally:
        connection.close()
    return [Entry(*row) for row in rows]
