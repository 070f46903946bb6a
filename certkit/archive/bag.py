"""BagIt bags (RFC 8493, version 1.0): written byte for byte the same from the same
payload, checked file by file, read safely from a zip.

A bag is a folder holding ``bagit.txt``, ``bag-info.txt``, ``manifest-sha256.txt`` (a
SHA-256 line per payload file under ``data/``) and ``tagmanifest-sha256.txt`` (the same
for the three tag files).  The manifests use ``sha256sum``'s layout, so
``cd BAG && sha256sum -c manifest-sha256.txt`` checks a bag without certkit.

The bag is written here rather than with the ``bagit`` library because that library
moves the payload in place and lists tag files in directory order, which is not the
same from one file system to another; the test suite checks that ``bagit`` accepts a bag
written here and rejects a tampered one.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import stat
import unicodedata
import zipfile
import zlib
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from certkit.errors import EnvironmentFailure, is_environmental

ALGORITHM = "sha256"
MANIFEST = "manifest-sha256.txt"
TAGMANIFEST = "tagmanifest-sha256.txt"
DECLARATION = "BagIt-Version: 1.0\nTag-File-Character-Encoding: UTF-8\n"
_LINE = re.compile(r"^([0-9a-fA-F]{64})[ \t]+\*?(.+)$")


class BagError(Exception):
    """The path is not a bag certkit can read (no bagit.txt, an unsafe zip, ...)."""


@dataclass(frozen=True)
class Change:
    """One way a bag differs from its manifests."""

    kind: str      # "added", "removed", "modified", "damaged"
    path: str      # relative to the bag, POSIX
    detail: str


def sha256_of(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _encode(path: str) -> str:
    """RFC 8493 §2.1.3: %, CR and LF in a manifest's file path are percent-encoded."""
    return path.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _decode(path: str) -> str:
    return path.replace("%0A", "\n").replace("%0a", "\n").replace("%0D", "\r") \
        .replace("%0d", "\r").replace("%25", "%")


def _entries(folder: Path) -> list[str]:
    """Every entry below ``folder`` that is not a directory (files, links, others),
    as sorted POSIX paths relative to it; links are listed, never followed."""
    found = []
    for parent, directories, files in os.walk(folder):
        for name in files + [d for d in directories if os.path.islink(os.path.join(parent, d))]:
            found.append(Path(parent, name).relative_to(folder).as_posix())
    return sorted(found)


def _info_text(info: list[tuple[str, str]]) -> str:
    lines = []
    for label, value in info:
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9-]*", label):
            raise ValueError(f"bag-info label {label!r} is not a single word")
        lines.append(f"{label}: {' '.join(str(value).split())}")
    return "".join(line + "\n" for line in lines)


def _write(path: Path, text: str) -> None:
    with open(path, "w", encoding="utf-8", newline="\n") as handle:
        handle.write(text)


def write_bag(folder: Path, info: list[tuple[str, str]]) -> str:
    """Make ``folder``, which already holds the payload in ``data/``, a complete bag.

    ``info`` are the bag-info.txt lines in order (label, value); Payload-Oxum is added.
    Returns the bag's hash: the SHA-256 of its tag manifest, which pins every file.
    """
    payload = _entries(folder / "data")
    lines, octets = [], 0
    for relative in payload:
        path = folder / "data" / relative
        if not _is_regular(path):
            raise BagError(f"{path}: the payload may hold regular files only")
        if "\\" in relative or any(c < " " or c in "\x85\u2028\u2029" for c in relative):
            raise BagError(f"{relative!r}: a payload file name may not hold a backslash or "
                           f"a line or control character")
        lines.append(f"{sha256_of(path)}  data/{_encode(relative)}\n")
        octets += path.stat().st_size
    _write(folder / "bagit.txt", DECLARATION)
    _write(folder / "bag-info.txt", _info_text([*info, ("Payload-Oxum",
                                                        f"{octets}.{len(payload)}")]))
    _write(folder / MANIFEST, "".join(lines))
    tags = sorted(["bagit.txt", "bag-info.txt", MANIFEST])
    _write(folder / TAGMANIFEST, "".join(f"{sha256_of(folder / t)}  {t}\n" for t in tags))
    return sha256_of(folder / TAGMANIFEST)


def read_info(folder: Path) -> dict[str, list[str]]:
    """bag-info.txt as label -> values (a label may repeat)."""
    info: dict[str, list[str]] = {}
    text = _read_tag(folder / "bag-info.txt")
    for line in (text or "").split("\n"):
        label, sep, value = line.partition(":")
        if sep:
            info.setdefault(label.strip(), []).append(value.strip())
    return info


def _is_regular(path: Path) -> bool:
    """A regular file, not a link, FIFO or device (reading those could block or not end)."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def _read_tag(path: Path) -> str | None:
    """A tag file's text; None when it is missing, not a regular file or not UTF-8."""
    if not _is_regular(path):
        return None
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None


def _manifest(folder: Path, name: str, changes: list[Change]) -> dict[str, str] | None:
    """path -> hash of one manifest; None when it is missing.  A malformed or unsafe line,
    a path listed twice, or (in the tag manifest) a payload path is a 'damaged' change
    naming the line."""
    path = folder / name
    if not os.path.lexists(path):
        return None
    text = _read_tag(path)
    if text is None:
        changes.append(Change("damaged", name, "not a readable UTF-8 text file"))
        return {}
    entries: dict[str, str] = {}
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    for number, line in enumerate(lines, start=1):
        match = _LINE.match(line)
        relative = _decode(match.group(2)) if match else ""
        parts = PurePosixPath(relative).parts
        if not match or relative.startswith("/") or ".." in parts or "\\" in relative:
            problem = f"expected '<SHA-256>  <relative path>', found {line!r}"
        elif relative in entries:
            problem = f"{relative!r} is listed twice"
        elif (name == TAGMANIFEST) == (parts[0] == "data"):
            problem = (f"{relative!r}: the payload is listed in {MANIFEST} only"
                       if name == TAGMANIFEST else f"{relative!r} is not under data/")
        else:
            entries[relative] = match.group(1).lower()
            continue
        changes.append(Change("damaged", name, f"line {number}: {problem}"))
    return entries


def check_bag(folder: Path) -> list[Change]:
    """Every file added to, removed from or modified in the bag at ``folder`` since its
    manifests were written, each named; an empty list when the bag is intact.

    Raises BagError when ``folder`` is not a bag at all (no bagit.txt and no manifest).
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise BagError(f"{folder}: not found, or not a folder or a .zip of a bag")
    if not any(os.path.lexists(folder / n) for n in ("bagit.txt", MANIFEST, TAGMANIFEST)):
        raise BagError(f"{folder}: not a bag (no bagit.txt, no {MANIFEST})")
    changes: list[Change] = []
    manifests = {}
    for name in (MANIFEST, TAGMANIFEST):
        entries = _manifest(folder, name, changes)
        if entries is None:
            changes.append(Change("removed", name, "the manifest is missing"))
            entries = {}
        manifests[name] = entries
    on_disk = set(_entries(folder))
    listed = sorted((relative, name, digest) for name, entries in manifests.items()
                    for relative, digest in entries.items())
    for relative, name, digest in listed:
        path = folder / relative
        if relative not in on_disk:
            changes.append(Change("removed", relative, f"listed in {name}, not in the bag"))
        elif not _is_regular(path):
            changes.append(Change("modified", relative, "is no longer a regular file"))
        elif (found := sha256_of(path)) != digest:
            changes.append(Change("modified", relative, f"SHA-256 {found}, {name} says "
                                                        f"{digest}"))
    for relative in sorted(on_disk - {r for r, _, _ in listed} - {TAGMANIFEST, MANIFEST}):
        changes.append(Change("added", relative, "in the bag, not in any manifest"))
    if manifests[TAGMANIFEST] and MANIFEST not in manifests[TAGMANIFEST]:
        changes.append(Change("damaged", TAGMANIFEST, f"does not list {MANIFEST}, so the "
                                                      f"payload manifest is unprotected"))
    if "bagit.txt" not in manifests[TAGMANIFEST] and _is_regular(folder / "bagit.txt") \
            and (folder / "bagit.txt").read_bytes() != DECLARATION.encode():
        changes.append(Change("damaged", "bagit.txt", "not a BagIt 1.0 declaration"))
    if not changes:
        oxum = read_info(folder).get("Payload-Oxum", [""])[0]
        payload = manifests[MANIFEST]
        octets = sum((folder / p).stat().st_size for p in payload)
        if oxum != f"{octets}.{len(payload)}":
            changes.append(Change("damaged", "bag-info.txt", f"Payload-Oxum {oxum!r}, the "
                                                             f"payload holds "
                                                             f"{octets}.{len(payload)}"))
    return changes


def bag_hash(folder: Path) -> str:
    """SHA-256 of the tag manifest: one hash that pins every file of the bag."""
    return sha256_of(Path(folder) / TAGMANIFEST)


# --------------------------------------------------------------------------- zip
def write_zip(folder: Path, target: Path, root: str, date) -> None:
    """A zip of the bag at ``folder`` under the folder name ``root``: sorted entries,
    every timestamp the campaign's ``date``, fixed permissions, so the same bag gives
    the same bytes.  (Zip timestamps start in 1980: an earlier date is refused.)"""
    if date.year < 1980:
        raise BagError(f"a zip cannot carry a date before 1980 ({date}); archive to a folder")
    stamp = (date.year, date.month, date.day, 0, 0, 0)
    with zipfile.ZipFile(target, "w") as archive:
        for relative in _entries(folder):
            item = zipfile.ZipInfo(f"{root}/{relative}", date_time=stamp)
            item.compress_type = zipfile.ZIP_DEFLATED
            item.external_attr = (stat.S_IFREG | 0o644) << 16
            item.create_system = 3  # Unix, so the permissions above are read as such
            large = (folder / relative).stat().st_size > (1 << 31)
            with open(folder / relative, "rb") as source, \
                    archive.open(item, "w", force_zip64=large) as sink:
                shutil.copyfileobj(source, sink, 1 << 20)


def _unsafe(name: str) -> str | None:
    """Why a zip member's name may not be extracted, or None.  Only canonical relative
    names pass: no empty, '.' or '..' part, so two names cannot land on one file."""
    path = name.replace("\\", "/")
    if path.startswith("/") or re.match(r"^[A-Za-z]:", path):
        return "an absolute path"
    parts = path.rstrip("/").split("/")
    if ".." in parts:
        return "a path with '..'"
    if "\\" in name:
        return "a path with a backslash"
    if any(part in ("", ".") for part in parts):
        return "a path with an empty or '.' part"
    return None


#: A member larger than this that expands more than MAX_RATIO-fold is refused: DEFLATE
#: cannot pass about 1032:1, measured data with a time column and noise stays well under
#: 20:1, so such a member is a "zip bomb" (a few megabytes declaring gigabytes).
MAX_RATIO = 100
RATIO_FROM = 16 << 20
#: More members than a bag of a campaign could hold (each costs a file and a manifest line).
MAX_MEMBERS = 100_000


def _oversized(member: zipfile.ZipInfo) -> str | None:
    """Why a member's declared size may not be extracted, or None.  The sizes are the
    zip's own (central directory); extraction stops at the declared size, so they bound
    what is written."""
    if member.file_size > RATIO_FROM and member.file_size > MAX_RATIO * member.compress_size:
        return (f"it declares {member.file_size} bytes from {member.compress_size} compressed "
                f"(more than {MAX_RATIO}:1): a zip bomb, not a bag's file")
    return None


def extract_zip(archive: Path, into: Path) -> Path:
    """Extract a zipped bag into the (empty) folder ``into``; return the bag's folder.

    Refuses, before writing anything, a member with an absolute path, a '..', '.' or
    empty part, a backslash, a symbolic link, a name repeated (also up to case and
    Unicode normalisation), a declared size more than MAX_RATIO times its compressed size
    (past RATIO_FROM bytes), more than MAX_MEMBERS members, or more bytes than the disk
    holds; then a zip without exactly one bag.  Any damage to the zip itself is a BagError.
    """
    try:
        with zipfile.ZipFile(archive) as handle:
            members = handle.infolist()
            if len(members) > MAX_MEMBERS:
                raise BagError(f"{archive}: refused: it holds {len(members)} members, more "
                               f"than a campaign's bag ({MAX_MEMBERS} at most)")
            seen = set()
            for member in members:
                why = _unsafe(member.filename) or _oversized(member)
                if why is None and stat.S_ISLNK(member.external_attr >> 16):
                    why = "a symbolic link"
                key = unicodedata.normalize("NFC", member.filename.rstrip("/")).casefold()
                if why is None and key in seen:
                    why = "a name the zip already holds (up to case or Unicode form)"
                seen.add(key)
                if why:
                    raise BagError(f"{archive}: refused to extract {member.filename!r}: {why}")
            size = sum(member.file_size for member in members)
            free = shutil.disk_usage(into).free
            if size > free // 2:
                raise BagError(f"{archive}: refused: it unpacks to {size} bytes and "
                               f"{free} bytes are free where it would be extracted")
            for member in members:
                handle.extract(member, into)
    except BagError:
        raise
    except (zipfile.BadZipFile, zipfile.LargeZipFile, zlib.error, NotImplementedError,
            RuntimeError, EOFError, ValueError, OSError) as error:
        if is_environmental(error):   # the disk, not the zip: full, forbidden, failing
            raise EnvironmentFailure.from_os_error(
                error, into, f"cannot extract {archive} here (set TMPDIR to extract it "
                             f"elsewhere)") from None
        raise BagError(f"{archive}: not a readable zip of a bag: {error}") from None

    def is_bag(folder: Path) -> bool:
        return any(os.path.lexists(folder / n) for n in ("bagit.txt", MANIFEST, TAGMANIFEST))

    if is_bag(into):
        return into
    roots = [p for p in into.iterdir() if p.is_dir() and is_bag(p)]
    if len(roots) != 1 or len(list(into.iterdir())) != 1:
        raise BagError(f"{archive}: expected one bag (a folder with bagit.txt) in the zip")
    return roots[0]
