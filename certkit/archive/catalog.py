"""The index of archived campaigns, so that a lab finds every campaign of an aircraft
type, a date range or a failed clause without opening the bags: in an SQLite file (the
embedded default, this module) or on a PostgreSQL server (a ``postgresql://`` URL,
:mod:`certkit.archive.catalog_postgresql`), with the same commands and guarantees.

A bag is catalogued only after it verifies intact; what is indexed comes from its
bag-info.txt and its archived results.json (a row per criterion,
:mod:`certkit.archive.catalog_rows`).  A bag is keyed by its hash (SHA-256 of its tag
manifest) and its location, so the same bag added twice is one entry and a copy elsewhere
is another; a location that holds another bag (changed and re-hashed since) is refused.

In SQLite each addition is one ``BEGIN IMMEDIATE`` transaction, which takes the database's
write lock at once (SQLite docs, "BEGIN TRANSACTION": "IMMEDIATE causes the database
connection to start a new write immediately"), with a generous busy timeout
(``sqlite3.connect(timeout=)``, SQLite's ``sqlite3_busy_timeout``): additions run one at
a time, two processes adding at once both land, and the check of the location and the
insertion see the same catalog.  The schema version is SQLite's ``PRAGMA user_version``
(SQLite docs, "PRAGMA user_version": an integer "available to applications"), as it
has been since version 1, so a catalog made by an earlier certkit is read and added to as
it is; the schema is created, and migrated (:data:`~certkit.archive.catalog_rows.MIGRATIONS`),
inside the addition's transaction.
"""

from __future__ import annotations

import contextlib
import errno
import os
import sqlite3
from pathlib import Path

from certkit.archive.catalog_rows import (TABLES, CatalogRefusal, Entry, changed_bag,
                                          describe, migration, newer_catalog,
                                          postgresql_url, schema_version, search_query,
                                          without_password)
from certkit.errors import CertkitInputError, EnvironmentFailure
from certkit.outputs import writing_failure

__all__ = ["CatalogRefusal", "Entry", "add", "describe", "search", "shown_catalog"]

TIMEOUT_S = 60.0


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
    if version > schema_version():
        connection.close()
        raise _catalog_error(path, newer_catalog(version))
    if version < 0 or not tables <= set(TABLES):
        connection.close()
        found = f"schema version {version}" if version < 0 else f"tables {sorted(tables)}"
        raise _catalog_error(path, f"not a certkit catalog of version {schema_version()} "
                                   f"({found})")
    return connection


def shown_catalog(catalog: str | Path) -> str:
    """The catalog's location as messages print it: a path, or a URL without its password."""
    return without_password(catalog)


def add(catalog: str | Path, bag: str | Path) -> tuple[Entry, bool]:
    """Verify the bag and index it; (entry, False) when it was already catalogued.

    ``catalog`` is an SQLite file's path or a ``postgresql://`` URL (a string).  A failed
    addition leaves the catalog as it was: on PostgreSQL the transaction is rolled back; an
    SQLite catalog this call created is removed again (with the folders it made), so a full
    or read-only disk leaves nothing behind."""
    url = postgresql_url(catalog)
    if url is not None:
        from certkit.archive import catalog_postgresql

        entry, verdicts = describe(bag)
        return entry, catalog_postgresql.insert(url, entry, verdicts, bag)
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
        version = connection.execute("PRAGMA user_version").fetchone()[0]
        if version > schema_version():        # made newer while this call waited
            connection.execute("ROLLBACK")
            raise _catalog_error(catalog, newer_catalog(version))
        for statement in migration(version, "INTEGER"):
            connection.execute(statement)   # (executescript would commit first)
        if version != schema_version():
            connection.execute(f"PRAGMA user_version = {schema_version()}")
        before = connection.execute(
            "SELECT bag_hash FROM campaigns WHERE location = ? AND bag_hash != ?",
            (entry.location, entry.bag_hash)).fetchone()
        if before is not None:
            connection.execute("ROLLBACK")
            raise changed_bag(bag, entry, before[0])
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
    """Catalogued campaigns matching every filter given (none: all of them), in the
    catalog at ``catalog`` (an SQLite file's path or a ``postgresql://`` URL); a catalog
    that does not exist yet is empty, and reading it creates nothing.

    ``text`` matches campaign id, title, aircraft or report number; ``aircraft``,
    ``campaign`` and ``clause`` are case-insensitive substrings; ``outcome`` is exact
    (case-insensitive); ``since``/``until`` (YYYY-MM-DD) keep campaigns tested within
    the range; ``verdict`` keeps campaigns with at least one criterion of that verdict
    (of a clause matching ``clause``, when given).
    """
    filters = dict(aircraft=aircraft, campaign=campaign, outcome=outcome, since=since,
                   until=until, verdict=verdict, clause=clause)
    url = postgresql_url(catalog)
    if url is not None:
        from certkit.archive import catalog_postgresql

        return catalog_postgresql.search(url, text, **filters)
    catalog = Path(catalog)
    if not catalog.exists():
        return []
    # SQLite's LIKE ignores the case of ASCII letters; its BINARY collation is byte order
    query, values = search_query("?", "LIKE", "", text, **filters)
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
