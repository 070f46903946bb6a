"""Writing outputs all or nothing, one run at a time, and never over anything certkit did
not write.

:func:`staged_folder` hands out a temporary folder beside the target; when the block
ends normally it replaces the target with it, otherwise it removes it (and any parent
folders it had to create).  It refuses targets whose replacement could destroy
something else: the campaign's own files, the current folder, a folder holding
files certkit does not write, a symbolic link.  :func:`beside` is the part it shares with
the archive (which never replaces anything):

* **one writer**: a lock on ``.NAME.lock`` beside the target (``fcntl.flock``, released by
  the system when a process dies); a second run waits up to :data:`LOCK_WAIT` seconds,
  then is refused;
* **no litter**: the temporary folders are named ``.NAME.tmp-certkit-XXXXXXXX`` (and
  ``.NAME.old-certkit-XXXXXXXX``); holding the lock, a run removes those an earlier,
  killed run left.  If the target is missing but an ``.old-`` folder exists (a run killed
  between the two renames of the fallback below), that earlier report is put back first;
* **atomic replacement**: the finished folder is synced to disk and exchanged with the
  old one in a single ``renameat2(RENAME_EXCHANGE)`` (Linux >= 3.15), so at every instant
  the target is the old complete folder or the new one; where the system or file system
  cannot, two renames (old aside, new in), with the gap between them covered above;
* **environment failures**: any OSError while writing (no space, permission, read-only,
  ...) becomes an :class:`~certkit.errors.EnvironmentFailure` naming the target.
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import functools
import os
import platform
import re
import shutil
import stat
import sys
import tempfile
import time
from pathlib import Path

from certkit import stop
from certkit.errors import CertkitInputError, EnvironmentFailure, named_file

try:
    import fcntl
except ImportError:  # not a POSIX system: no lock (documented in the README)
    fcntl = None

#: Seconds a run waits for another run writing the same target before it is refused.
LOCK_WAIT = 60.0


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


def check_file_target(target: Path, inputs: list[Path], key: str) -> None:
    """Raise CertkitInputError when the single file ``target`` (``audit -o``, ``--json``)
    cannot be written without loss: it is a folder, or it is one of ``inputs`` (the
    campaign's spec and data files, a baseline), by name or by link."""
    if target.is_dir():
        raise CertkitInputError.single(str(target), None, key, "is a folder; give a file "
                                                               "name for it")
    for item in inputs:
        same = target.resolve() == Path(item).resolve() or (
            target.exists() and Path(item).exists() and os.path.samefile(target, item))
        if same:
            raise CertkitInputError.single(
                str(target), None, key, f"is the input {item}; writing there would replace "
                                        f"it: choose another file")


def _folder_mode(final: Path) -> int:
    """Keep an existing folder's permissions; a new one gets the umask's."""
    if final.exists():
        return stat.S_IMODE(final.stat().st_mode)
    mask = os.umask(0)
    os.umask(mask)
    return 0o777 & ~mask


# ------------------------------------------------------------------ renameat2 (Linux)
_AT_FDCWD = -100
RENAME_NOREPLACE = 1
RENAME_EXCHANGE = 2
# renameat2's system call number where the C library lacks the wrapper (glibc < 2.28)
#: renameat2's system-call number per machine, from the Linux kernel's syscall tables
#: (arch/x86/entry/syscalls/syscall_64.tbl and syscall_32.tbl, include/uapi/asm-generic/
#: unistd.h for arm64, riscv and loongarch, arch/arm/tools/syscall.tbl,
#: arch/powerpc/kernel/syscalls/syscall.tbl, arch/s390/kernel/syscalls/syscall.tbl).
_SYSCALL_RENAMEAT2 = {"x86_64": 316, "amd64": 316, "i386": 353, "i686": 353, "aarch64": 276,
                      "arm64": 276, "riscv64": 276, "loongarch64": 276, "armv7l": 382,
                      "armv6l": 382, "ppc64le": 357, "ppc64": 357, "s390x": 347}


def load_renameat2(libc, machine: str):
    """The C library's renameat2, or one calling the system call by number; None when
    neither is known here."""
    function = getattr(libc, "renameat2", None)
    if function is not None:
        function.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p,
                             ctypes.c_uint]
        return function
    number = _SYSCALL_RENAMEAT2.get(machine.lower())
    syscall = getattr(libc, "syscall", None)
    if number is None or syscall is None:
        return None
    syscall.restype = ctypes.c_long

    def by_number(old_dir, old, new_dir, new, flags):
        return syscall(ctypes.c_long(number), ctypes.c_int(old_dir), ctypes.c_char_p(old),
                       ctypes.c_int(new_dir), ctypes.c_char_p(new), ctypes.c_uint(flags))

    return by_number


@functools.cache
def _renameat2():
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(None, use_errno=True)
    except OSError:
        return None
    return load_renameat2(libc, platform.machine())


def rename2(source: Path, target: Path, flags: int) -> bool:
    """renameat2(source, target, flags): True when done, False when this system or file
    system cannot (no renameat2, or the flag refused); any other failure is an OSError."""
    function = _renameat2()
    if function is None:
        return False
    if function(_AT_FDCWD, os.fsencode(source), _AT_FDCWD, os.fsencode(target), flags) == 0:
        return True
    number = ctypes.get_errno()
    if number in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(number, os.strerror(number), str(source), None, str(target))


def rename_no_replace(source: Path, target: Path) -> None:
    """Move ``source`` to ``target`` only if nothing is there, atomically where the kernel
    offers renameat2(RENAME_NOREPLACE); raises FileExistsError otherwise."""
    try:
        if rename2(source, target, RENAME_NOREPLACE):
            return
    except FileExistsError:
        raise FileExistsError(errno.EEXIST, "exists", str(target)) from None
    # no renameat2 here: check, then rename (a folder) or link (a file), which fails
    # rather than replace a file; only an empty folder made in between could be replaced
    if os.path.lexists(target):
        raise FileExistsError(errno.EEXIST, "exists", str(target))
    if source.is_dir():
        os.rename(source, target)
        return
    try:
        os.link(source, target)
    except FileExistsError:
        raise
    except OSError:   # a file system without hard links: copy into a file made exclusively
        with open(source, "rb") as reader, open(target, "xb") as writer:
            shutil.copyfileobj(reader, writer, 1 << 20)


# ------------------------------------------------------------------ lock, litter, swap
def _lock_path(final: Path) -> Path:
    return final.parent / f".{final.name}.lock"


def _temporary_prefix(final: Path, kind: str) -> str:
    return f".{final.name}.{kind}-certkit-"


def _litter(final: Path) -> list[Path]:
    """Temporary folders of earlier runs into ``final``: ``.NAME.tmp-certkit-XXXXXXXX`` and
    ``.NAME.old-certkit-XXXXXXXX`` (and ``.NAME.tmp-XXXXXXXX`` / ``.NAME.old-XXXXXXXX``,
    the names certkit used before it locked its targets)."""
    pattern = re.compile(rf"\.{re.escape(final.name)}\.(tmp|old)-(certkit-)?[a-z0-9_]{{8}}")
    found = []
    for entry in os.scandir(final.parent):
        if pattern.fullmatch(entry.name) and entry.is_dir(follow_symlinks=False):
            found.append(Path(entry.path))
    return found


def _clear_litter(final: Path) -> None:
    """Called holding the lock, so no live run owns them: put back an earlier report that a
    killed run had moved aside (the target missing), then remove the rest.  Best effort:
    what cannot be removed (another user's, say) stays, and the run goes on."""
    litter = _litter(final)
    old = [p for p in litter if p.name.startswith(f".{final.name}.old-")]
    if old and not os.path.lexists(final):
        newest = max(old, key=lambda p: p.stat().st_mtime_ns)
        with contextlib.suppress(OSError):
            os.rename(newest, final)
            litter.remove(newest)
    for path in litter:
        with contextlib.suppress(OSError):
            _remove_tree(path)


# flock refused by the file system (some network shares): write without the lock
_NO_LOCKING = (errno.ENOLCK, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP)


@contextlib.contextmanager
def _locked(final: Path, target: Path):
    """Hold ``.NAME.lock`` beside ``final``; wait up to LOCK_WAIT seconds for another run."""
    if fcntl is None:
        yield
        return
    path = _lock_path(final)
    deadline = time.monotonic() + LOCK_WAIT
    flags = os.O_RDONLY | os.O_CREAT | os.O_CLOEXEC | getattr(os, "O_NOFOLLOW", 0)
    while True:
        descriptor = os.open(path, flags, 0o666)
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(descriptor)
            if time.monotonic() >= deadline:
                raise EnvironmentFailure(target, f"another certkit run is writing it (it holds "
                                                 f"{path}); wait for that run to end, or write "
                                                 f"to another folder") from None
            time.sleep(0.1)
            continue
        except OSError as error:
            os.close(descriptor)
            if error.errno not in _NO_LOCKING:
                raise
            descriptor = None
            break
        except BaseException:
            os.close(descriptor)
            raise
        # the run that held it removes the file as it ends: lock the file now there
        with contextlib.suppress(FileNotFoundError):
            if os.path.samestat(os.fstat(descriptor), os.stat(path)):
                break
        os.close(descriptor)
    try:
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(path)
        if descriptor is not None:
            os.close(descriptor)


# a path that cannot be written where it points: bad input, not the machine's fault (EEXIST:
# a file stands where a folder of the path must be made)
_NOT_A_PLACE = (errno.ENOENT, errno.ENOTDIR, errno.EISDIR, errno.ENAMETOOLONG, errno.ELOOP,
                errno.EEXIST)


def writing_failure(error: OSError, path: str | Path, doing: str = "cannot write the outputs",
                    key: str = "--output", staging: Path | None = None) -> Exception:
    """The one mapping of an OSError met while writing ``path``: a path that cannot be
    written where it points (a missing folder, a file in the way, a name too long) is bad
    input (CertkitInputError, exit 2); anything else (no space, no permission, read-only,
    ...) is the machine's (EnvironmentFailure, exit 4).  A file inside ``staging`` is not
    named: the user never sees that folder."""
    if staging is not None and error.filename is not None and \
            Path(os.fsdecode(error.filename)).is_relative_to(staging):
        error = OSError(error.errno, error.strerror)
    if error.errno in _NOT_A_PLACE:
        why = "a file stands where a folder must be" if error.errno == errno.EEXIST else \
            error.strerror or error
        return CertkitInputError.single(str(path), None, key,
                                        f"{doing}: {why}{named_file(error, path)}")
    return EnvironmentFailure.from_os_error(error, path, doing)


@contextlib.contextmanager
def beside(target: str | Path):
    """Yield a new temporary folder beside ``target`` (creating missing parent folders),
    holding the target's lock, after removing what killed runs left there; the folder
    (and any parents created) is removed when the block ends, however it ends.  An
    OSError becomes an EnvironmentFailure naming ``target``."""
    target = Path(target)
    final = target.resolve()
    created: list[Path] = []
    staging = None
    doing = "cannot create the output folder here"
    try:
        for folder in reversed([p for p in [final.parent, *final.parent.parents]
                                if not p.exists()]):
            folder.mkdir()
            created.insert(0, folder)
        with _locked(final, target):
            _clear_litter(final)
            staging = Path(tempfile.mkdtemp(prefix=_temporary_prefix(final, "tmp"),
                                            dir=final.parent))
            doing = "cannot write the outputs"
            try:
                yield staging
            finally:
                with contextlib.suppress(OSError):
                    _remove_tree(staging)
        created = []
    except OSError as error:
        raise writing_failure(error, target, doing, staging=staging) from None
    finally:
        for folder in created:
            with contextlib.suppress(OSError):
                folder.rmdir()


def _sync_tree(folder: Path) -> None:
    """fsync every file and folder below ``folder``, so what is moved into place is on the
    disk, not only in the cache (a full disk can show only here)."""
    for parent, _, files in os.walk(folder):
        for name in files:
            descriptor = os.open(os.path.join(parent, name), os.O_RDONLY)
            try:
                os.fsync(descriptor)
            finally:
                os.close(descriptor)
        _sync_folder(Path(parent))


def _sync_folder(folder: Path) -> None:
    descriptor = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    except OSError as error:   # some file systems cannot sync a folder: nothing to do
        if error.errno not in (errno.EINVAL, errno.ENOTSUP, errno.EBADF):
            raise
    finally:
        os.close(descriptor)


def _replace(staging: Path, final: Path) -> None:
    """Put the finished ``staging`` folder at ``final``; an existing ``final`` ends up at
    ``staging`` (removed by :func:`beside`)."""
    if not os.path.lexists(final):
        rename_no_replace(staging, final)
    elif not rename2(staging, final, RENAME_EXCHANGE):
        old = staging.with_name(staging.name.replace(".tmp-", ".old-", 1))
        os.rename(final, old)        # a kill here leaves old aside: the next run puts it back
        try:
            os.rename(staging, final)
        except BaseException:
            os.rename(old, final)
            raise
        os.rename(old, staging)
    _sync_folder(final.parent)


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

    Raises CertkitInputError for a target it will not replace, EnvironmentFailure when
    the machine refuses (no space, no permission, another run writing it).
    """
    target = Path(target)
    check_target(target, inputs, own_paths)
    final = target.resolve()
    with beside(target) as staging:
        check_target(target, inputs, own_paths)    # again, now that no other run can change it
        if final.exists() and not os.access(final, os.W_OK):   # made read-only: keep it
            raise PermissionError(errno.EACCES, "the folder is read-only", str(final))
        yield staging
        staging.chmod(_folder_mode(final))  # mkdtemp makes it 0700
        _sync_tree(staging)
        stop.raise_if_stopped()   # a stop a finaliser dropped: the outputs are not made final
        _replace(staging, final)


def write_text_atomically(path: str | Path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` through a temporary file beside it, so a reader
    sees the old file or the new one, never a part."""
    write_bytes_atomically(path, text.encode("utf-8"))


def write_bytes_atomically(path: str | Path, data: bytes, private: bool = False) -> None:
    """Write ``data`` to ``path`` through a temporary file beside it (the old file or the
    new one, never a part); ``private``: readable by its owner only (0600), else what the
    umask allows."""
    path = Path(path)
    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.tmp-", dir=path.parent)
    except OSError as error:   # name the file asked for, not a temporary one never made
        raise type(error)(error.errno, error.strerror, str(path)) from None
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        if not private:   # mkstemp makes the file private (0600)
            mask = os.umask(0)
            os.umask(mask)
            os.chmod(temporary, 0o666 & ~mask)
        stop.raise_if_stopped()
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temporary)
        raise
