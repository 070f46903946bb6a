"""Writing an output folder all or nothing, and never over anything certkit did not write.

:func:`staged_folder` hands out a temporary folder beside the target; when the block
ends normally it replaces the target with it, otherwise it removes it (and any parent
folders it had to create).  It refuses targets whose replacement could destroy
something else: the campaign's own files, the current folder, a folder holding
files certkit does not write, a symbolic link.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from pathlib import Path

from certkit.errors import CertkitInputError


def _refuse(target: str | Path, message: str) -> CertkitInputError:
    return CertkitInputError.single(str(target), None, "--output", message)


def _remove_tree(path: Path) -> None:
    def make_writable_and_retry(function, name, _):
        os.chmod(name, stat.S_IRWXU)
        parent = os.path.dirname(name)
        os.chmod(parent, stat.S_IRWXU)
        function(name)

    if path.exists():
        shutil.rmtree(path, onerror=make_writable_and_retry)


def _foreign_entries(folder: Path, own_paths: set[str]) -> list[str]:
    """Entries under ``folder`` that are not among the relative paths certkit writes."""
    foreign = []
    for path in sorted(folder.rglob("*")):
        relative = path.relative_to(folder).as_posix()
        expected_folder = any(own.startswith(relative + "/") for own in own_paths)
        if path.is_symlink() or (path.is_dir() and not expected_folder) or (
                not path.is_dir() and relative not in own_paths):
            foreign.append(relative)
    return foreign


def check_target(target: Path, inputs: list[Path], own_paths: set[str]) -> None:
    """Raise CertkitInputError when replacing ``target`` could lose anything."""
    if str(target) in ("", "."):
        raise _refuse(target, "give a folder name for the outputs, not the current folder")
    if target.is_symlink():
        raise _refuse(target, "is a symbolic link; give a real folder for the outputs")
    resolved = target.resolve()
    if Path.cwd().resolve().is_relative_to(resolved):
        raise _refuse(target, "is the current folder or one above it; certkit replaces the "
                              "output folder and will not replace that")
    for item in inputs:
        if Path(item).resolve().is_relative_to(resolved):
            raise _refuse(target, f"would contain the input {item}; replacing it would delete "
                                  f"the campaign's own files: choose another output folder")
    if resolved.exists():
        if not resolved.is_dir():
            raise _refuse(target, "exists and is not a folder")
        foreign = _foreign_entries(resolved, own_paths)
        if foreign:
            shown = ", ".join(foreign[:5]) + (", ..." if len(foreign) > 5 else "")
            raise _refuse(target, f"exists and holds files certkit did not write ({shown}); "
                                  f"certkit only replaces its own output folders")


def _folder_mode(final: Path) -> int:
    """Keep an existing folder's permissions; a new one gets the umask's."""
    if final.exists():
        return stat.S_IMODE(final.stat().st_mode)
    mask = os.umask(0)
    os.umask(mask)
    return 0o777 & ~mask


@contextlib.contextmanager
def staged_folder(target: str | Path, inputs: list[Path], own_paths: set[str]):
    """Yield a temporary folder that replaces ``target`` when the block succeeds.

    Parameters
    ----------
    target : path
        The output folder.
    inputs : list of Path
        Files the outputs are computed from; the target may not contain any of them.
    own_paths : set of str
        Relative paths of the files certkit writes into the folder (``tables/x.csv``);
        an existing target holding anything else is refused rather than replaced.
    """
    target = Path(target)
    check_target(target, inputs, own_paths)
    final = target.resolve()
    parent = final.parent
    created: list[Path] = []
    try:
        missing = [p for p in [parent, *parent.parents] if not p.exists()]
        for folder in reversed(missing):
            folder.mkdir()
            created.append(folder)
        staging = Path(tempfile.mkdtemp(prefix=f".{final.name}.tmp-", dir=parent))
    except OSError as error:
        for folder in reversed(created):
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise _refuse(target, f"cannot create the output folder here: {error.strerror or error}") \
            from None
    staging.chmod(_folder_mode(final))  # mkdtemp makes it 0700
    old = None
    try:
        yield staging
        if final.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{final.name}.old-", dir=parent))
            old.rmdir()
            final.rename(old)
        staging.rename(final)
    except BaseException:
        _remove_tree(staging)
        if old is not None and old.exists() and not final.exists():
            old.rename(final)
        for folder in reversed(created):
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise
    if old is not None:
        _remove_tree(old)


def write_text_atomically(path: str | Path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` through a temporary file beside it, so a reader
    sees the old file or the new one, never a part."""
    path = Path(path)
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.tmp-", dir=path.parent)
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="\n") as stream:
            stream.write(text)
        # mkstemp makes the file private (0600); a written file gets what the umask allows
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(temporary, 0o666 & ~mask)
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temporary)
        raise
