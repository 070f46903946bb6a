"""The archive catalog on a PostgreSQL server, for a lab that shares one: the catalog is a
``postgresql://user@host[:port]/database`` URL (libpq's connection URI, PostgreSQL docs,
"Connection Strings"), read with psycopg 3 (``pip install 'certkit[postgresql]'``).  The
tables and the search are SQLite's (:mod:`certkit.archive.catalog_rows`); so are the
guarantees, kept as follows.

* **One transaction per addition**, rolled back whole when anything fails: the schema
  it created, its campaign and its verdicts go with it (PostgreSQL's DDL is
  transactional), so a failed addition leaves nothing.
* **The same bag twice is one entry**: ``INSERT ... ON CONFLICT DO NOTHING`` on the
  primary key (bag_hash, location), whose outcome is atomic even when another
  transaction inserts the same key at the same moment: one inserts, the other does
  nothing (PostgreSQL docs, "INSERT", section "ON CONFLICT Clause").
* **A bag changed at a catalogued location is refused**: the addition first takes a
  transaction-level advisory lock on its location (``pg_advisory_xact_lock``,
  PostgreSQL docs, "Advisory Lock Functions" and "Advisory Locks"), released at commit
  or rollback, so two additions at one location run one after the other and the second,
  in READ COMMITTED, sees what the first committed (PostgreSQL docs, "Transaction
  Isolation": each statement sees the rows committed before it began).  Additions at
  other locations do not wait for each other, unlike SQLite's one writer at a time.
* **The schema is created and migrated by certkit**, under another advisory lock (so two
  processes creating it at once do not collide: ``CREATE TABLE IF NOT EXISTS`` alone can
  fail with a unique violation when another transaction creates the table at the same
  time) in the addition's own transaction.  Its version is the one row of the table
  ``certkit_catalog``; a catalog of a newer certkit is refused, not changed.
* A wait longer than :data:`TIMEOUT_S` for a lock (``lock_timeout``) fails as the
  machine's refusal, as SQLite's busy timeout does; a deadlock or serialization failure
  (PostgreSQL docs, "Serialization Failure Handling") is retried.
* Reading a database in which no catalog was made yet finds it empty and creates nothing.

What the connection refuses is said without a traceback and without the URL's password:
a server that cannot be reached, is full or was shut down is the machine's refusal
(:class:`~certkit.errors.EnvironmentFailure`, exit 4); a login the server refuses (user,
password, unknown database) or a URL it cannot read is bad input (exit 2).
"""

from __future__ import annotations

import hashlib
import os
import re
import urllib.parse
from pathlib import Path

from certkit.archive.catalog_rows import (FIELDS, TABLES, Entry, changed_bag, migration,
                                          newer_catalog, schema_version, search_query,
                                          without_password)
from certkit.errors import CertkitInputError, EnvironmentFailure

TIMEOUT_S = 60.0
CONNECT_TIMEOUT_S = 10
#: The first key of certkit's advisory locks ("ck" in ASCII); the second is 0 for the
#: schema, else a location's :func:`location_key`.
LOCK_KEY = 0x636B
RETRIES = 5
META = "certkit_catalog"


def _input_error(url: str, message: str) -> CertkitInputError:
    return CertkitInputError.single(without_password(url), None, "--catalog", message)


def _said(error: Exception, url: str) -> str:
    """The driver's message on one line, the passwords of ``url`` (its user part's, its
    ``password=`` parameter's) blanked out, should libpq ever echo one."""
    text = "; ".join(line.strip() for line in str(error).splitlines() if line.strip())
    text = re.sub(r"^connection failed: ", "", text)
    text = re.sub(r"\b(FATAL|ERROR):\s+", "", text)
    try:
        parts = urllib.parse.urlsplit(url)
        passwords = [parts.password, *urllib.parse.parse_qs(parts.query).get("password", [])]
    except ValueError:
        passwords = []
    for password in filter(None, passwords):
        text = text.replace(password, "***")
    return text


# What a login refused for what the URL says reads like (libpq's and the server's
# wording): the user's to correct, not the machine's
_REFUSED_LOGIN = ("password authentication failed", "no password supplied",
                  "authentication failed", "pg_hba.conf", "does not exist",
                  "permission denied", "invalid ", "not permitted to log in")


def connect(url: str):
    """An autocommit connection to the catalog's server (transactions are explicit)."""
    try:
        import psycopg
    except ImportError:
        raise _input_error(url, "a PostgreSQL catalog needs psycopg, which is not "
                                "installed: pip install 'certkit[postgresql]'") from None
    try:
        options = psycopg.conninfo.conninfo_to_dict(url)
    except psycopg.Error as error:
        raise _input_error(url, f"not a PostgreSQL URL that libpq reads "
                                f"({_said(error, url)}); expected "
                                f"postgresql://user@host[:port]/database") from None
    if "PGCONNECT_TIMEOUT" not in os.environ:
        options.setdefault("connect_timeout", CONNECT_TIMEOUT_S)
    options.setdefault("application_name", "certkit")
    try:
        return psycopg.connect(autocommit=True, **options)
    except psycopg.Error as error:
        said = _said(error, url)
        if isinstance(error, psycopg.ProgrammingError) or "connection option" in said:
            raise _input_error(url, f"not a PostgreSQL URL that libpq reads ({said}); "
                                    f"expected postgresql://user@host[:port]/database") \
                from None
        if any(words in said for words in _REFUSED_LOGIN):
            raise _input_error(url, f"the server refused the connection: {said}; check the "
                                    f"URL's user, host and database, and the password "
                                    f"(~/.pgpass or PGPASSWORD)") from None
        raise EnvironmentFailure(without_password(url), f"cannot connect to the catalog's "
                                                        f"server: {said}; check that it is "
                                                        f"running and reachable, and try "
                                                        f"again") from None


def failure(url: str, error: Exception, doing: str) -> Exception:
    """The one mapping of a PostgreSQL error on the catalog at ``url``, by its SQLSTATE
    (PostgreSQL docs, "PostgreSQL Error Codes"): what the server or the machine refuses
    (a lock held too long, collisions retried in vain, a full disk, a lost connection, a
    shutdown, a read-only standby, no privilege) is an EnvironmentFailure (exit 4);
    anything else means the database holds something that is not a certkit catalog
    (exit 2)."""
    import psycopg

    shown = without_password(url)
    state = getattr(error, "sqlstate", None) or ""
    said = _said(error, url)
    if state == "55P03":
        return EnvironmentFailure(shown, f"{doing}: another process held it for "
                                         f"{TIMEOUT_S:g} s; try again when it has finished")
    if state[:2] == "40":                   # a deadlock or serialization failure, retried
        return EnvironmentFailure(shown, f"{doing}: it collided with other additions "
                                         f"{RETRIES} times ({said}); try again")
    if state == "42501":
        return EnvironmentFailure(shown, f"{doing}: {said}; the role needs the privilege "
                                         f"(the database's owner, or GRANT CREATE ON SCHEMA "
                                         f"and SELECT, INSERT on its tables)")
    if state == "25006":
        return EnvironmentFailure(shown, f"{doing}: the server is read-only ({said}); "
                                         f"name the primary server")
    if state[:2] in ("08", "53", "57", "58", "XX") or (
            not state and isinstance(error, psycopg.OperationalError)):
        return EnvironmentFailure(shown, f"{doing}: the server failed or the connection was "
                                         f"lost ({said}); check the server and try again")
    return _input_error(url, f"{doing}: not a certkit catalog (PostgreSQL says: {said})")


def _version(connection, url: str) -> int:
    """The catalog's schema version, 0 when none was made in this database yet; refuses a
    database whose certkit tables were not made by certkit.

    The tables are looked up before certkit_catalog, one statement each.  One transaction
    makes them all, but another process's may commit between two look-ups (a name is
    looked up in the system catalogs as they are at that moment, not as of the
    statement's snapshot: tests/test_catalog.py's eight additions creating a catalog at
    once saw campaigns and no certkit_catalog when they were looked up the other way
    round); tables seen first, and no certkit_catalog seen after them, are not certkit's."""
    found = [name for name in TABLES if connection.execute(
        "SELECT to_regclass(%s)", (name,)).fetchone()[0] is not None]
    if connection.execute("SELECT to_regclass(%s)", (META,)).fetchone()[0] is None:
        if found:
            raise _input_error(url, f"not a certkit catalog: the database holds table(s) "
                                    f"{', '.join(found)} without {META}")
        return 0
    row = connection.execute(f"SELECT schema_version FROM {META}").fetchone()
    version = row[0] if row else 0
    if version > schema_version():
        raise _input_error(url, newer_catalog(version))
    return version


def _migrate(connection, url: str) -> None:
    """Create or migrate the schema unless it is current: under the schema's advisory lock,
    the version read again once it is held (another process may have just made it)."""
    if _version(connection, url) == schema_version():
        return
    connection.execute("SELECT pg_advisory_xact_lock(%s::integer, 0)", (LOCK_KEY,))
    version = _version(connection, url)
    if version == schema_version():
        return
    for statement in migration(version, "BIGINT"):
        connection.execute(statement)
    connection.execute(f"CREATE TABLE IF NOT EXISTS {META} (schema_version INTEGER NOT NULL)")
    connection.execute(f"DELETE FROM {META}")
    connection.execute(f"INSERT INTO {META} VALUES (%s)", (schema_version(),))


def location_key(location: str) -> int:
    """The second key of a location's advisory lock: 32 bits of its SHA-256 (two locations
    sharing a key only wait for each other)."""
    return int.from_bytes(hashlib.sha256(location.encode("utf-8")).digest()[:4], "big",
                          signed=True)


def _add_rows(connection, entry: Entry, verdicts: list[tuple], bag: str | Path) -> bool:
    """The addition's statements, in its transaction: lock the location, refuse another
    bag there, insert the campaign and its verdicts (each once)."""
    connection.execute("SELECT pg_advisory_xact_lock(%s::integer, %s::integer)",
                       (LOCK_KEY, location_key(entry.location)))
    before = connection.execute(
        "SELECT bag_hash FROM campaigns WHERE location = %s AND bag_hash <> %s LIMIT 1",
        (entry.location, entry.bag_hash)).fetchone()
    if before is not None:
        raise changed_bag(bag, entry, before[0])
    inserted = connection.execute(
        f"INSERT INTO campaigns ({', '.join(FIELDS)}) "
        f"VALUES ({', '.join(['%s'] * len(FIELDS))}) ON CONFLICT DO NOTHING",
        list(entry.as_dict().values())).rowcount
    with connection.cursor() as cursor:
        cursor.executemany("INSERT INTO verdicts VALUES (%s, %s, %s, %s, %s, %s) "
                           "ON CONFLICT DO NOTHING", verdicts)
    return inserted == 1


def insert(url: str, entry: Entry, verdicts: list[tuple], bag: str | Path) -> bool:
    """Add the verified bag's rows to the catalog at ``url`` in one transaction; False when
    the bag was already catalogued at its location.  Raises CatalogRefusal when another
    bag is catalogued at its location."""
    connection = connect(url)
    import psycopg
    from psycopg import errors

    try:
        attempt = 1
        while True:
            try:
                with connection.transaction():
                    connection.execute(f"SET LOCAL lock_timeout = '{TIMEOUT_S:g}s'")
                    _migrate(connection, url)
                    return _add_rows(connection, entry, verdicts, bag)
            except (errors.SerializationFailure, errors.DeadlockDetected):
                if attempt == RETRIES:
                    raise
                attempt += 1
    except psycopg.Error as error:
        raise failure(url, error, "cannot add to the catalog") from None
    finally:
        connection.close()


def search(url: str, text: str | None = None, **filters) -> list[Entry]:
    """:func:`certkit.archive.catalog.search` on the catalog at ``url``: ILIKE for
    SQLite's case-insensitive LIKE, the "C" collation for its byte order."""
    query, values = search_query("%s", "ILIKE", ' COLLATE "C"', text, **filters)
    connection = connect(url)
    import psycopg

    try:
        with connection.transaction():
            connection.execute("SET TRANSACTION READ ONLY")
            if _version(connection, url) == 0:
                return []
            rows = connection.execute(query, values).fetchall()
    except psycopg.Error as error:
        raise failure(url, error, "cannot read the catalog") from None
    finally:
        connection.close()
    return [Entry(*row) for row in rows]
