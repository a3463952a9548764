"""Output files: every path checked before any work, then written all at once onto itself.

One place decides what an output path may be and how it is written, for every file the tool
writes (``-o``, ``--pdf``, ``--csv``, ``--plot``, ``--step``, ``--stl``, ``init``):

- a symbolic link is refused (the user gives the file it points at): a link planted in a shared
  folder cannot make the tool replace, or change the permissions of, a file elsewhere. The one
  exception is the system's own stream links (``/dev/stdout``, ``/dev/fd/1``,
  ``/proc/self/fd/1``) to a character device or FIFO, which are written into. A folder on the
  way that is a link another user planted in a shared sticky folder is refused too
  (:func:`planted_link`, the kernel's ``protected_symlinks`` rule);
- a missing parent folder is refused; no folder is ever created;
- an existing character device or FIFO (``/dev/null``, a pipe a reader holds open) is written
  into, never replaced; a block device, socket or folder is refused;
- a file is staged beside the path (an anonymous ``O_TMPFILE`` on Linux) and renamed onto the
  path itself, never onto a resolved target; an existing regular file's permission bits (and
  owner and group, where the process may set them) are kept, a new file gets the umask's mode.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from spiralcap.core.errors import DataError, InputError

#: Longest file name (one path component) in bytes, where the system does not say (Linux,
#: macOS and Windows file systems all allow 255).
NAME_MAX = 255

#: Outputs that are written through (opened and written in place, never replaced by a file).
WRITE_THROUGH = ("character device", "FIFO")

#: Folders whose links are the system's own streams (``/dev/stdout`` -> ``/proc/self/fd/1``).
_STREAM_FOLDERS = ("/dev", "/proc")

_KINDS = (
    (stat.S_ISCHR, "character device"),
    (stat.S_ISFIFO, "FIFO"),
    (stat.S_ISBLK, "block device"),
    (stat.S_ISSOCK, "socket"),
    (stat.S_ISDIR, "folder"),
)


def _kind(mode: int) -> str | None:
    if stat.S_ISREG(mode):
        return None
    return next((name for test, name in _KINDS if test(mode)), "special file")


def _stream_link(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is one of the system's stream links: it lies under ``/dev`` or
    ``/proc``, in a folder nobody but root or this user may change, and leads to a character
    device or FIFO."""
    absolute = os.path.abspath(path)
    if not absolute.startswith(tuple(f + os.sep for f in _STREAM_FOLDERS)):
        return False
    try:
        folder = os.stat(os.path.dirname(absolute))
        mode = os.stat(absolute).st_mode
    except OSError:
        return False
    trusted = folder.st_uid in (0, os.geteuid()) and not folder.st_mode & 0o022
    return trusted and (stat.S_ISCHR(mode) or stat.S_ISFIFO(mode))


def special_file(path: str | os.PathLike[str]) -> str | None:
    """What an existing output that is not a regular file is: ``"symbolic link"``,
    ``"character device"``, ``"FIFO"``, ``"block device"``, ``"socket"``, ``"folder"``; None
    for a regular file or a path that does not exist yet.

    The link itself is looked at, not what it points at; only the system's stream links
    (``/dev/stdout`` to a pipe or terminal) count as the device or FIFO they lead to.
    """
    try:
        mode = os.lstat(path).st_mode
    except OSError:
        return None
    if stat.S_ISLNK(mode):
        if not _stream_link(path):
            return "symbolic link"
        mode = os.stat(path).st_mode
    return _kind(mode)


def _link_refusal(path: str) -> str:
    try:
        points_at = os.readlink(path)
    except OSError:
        points_at = "?"
    return (
        f"a path that is not a symbolic link (it links to {points_at!r}; give the real path: "
        "outputs are never written through a link)"
    )


def planted_link(path: str | os.PathLike[str]) -> str | None:
    """The first folder on the way to ``path`` that is a symbolic link another user planted in a
    shared folder (world-writable and sticky, like ``/tmp``), or None.

    The kernel's own rule (``fs.protected_symlinks``), applied whether or not the kernel is set
    to: such a link is followed only when this process or the shared folder's owner owns it.
    Links in private folders (``/var/run``, a project folder linked from home) are followed.
    """
    parts = Path(os.path.abspath(path)).parent.parts
    for i in range(2, len(parts) + 1):
        here = Path(*parts[:i])
        try:
            link = os.lstat(here)
            if not stat.S_ISLNK(link.st_mode):
                continue
            folder = os.stat(here.parent)
        except OSError:
            return None  # a missing folder: said by the caller
        shared = folder.st_mode & stat.S_ISVTX and folder.st_mode & stat.S_IWOTH
        if shared and link.st_uid not in (os.geteuid(), folder.st_uid):
            return str(here)
    return None


def _missing_folder(path: str) -> tuple[str | None, str]:
    """The first folder on the way to ``path`` that does not exist (None if all do), and the
    nearest existing one above it."""
    parent = os.path.dirname(path)
    missing = None
    while parent and not os.path.lexists(parent):
        missing = parent
        up = os.path.dirname(parent)
        if up == parent:
            break
        parent = up
    return missing, parent or "."


def check_output(flag: str, path: str) -> str | None:
    """Refuse an output path that cannot or must not be written, before any computation.

    Parameters
    ----------
    flag : str
        The option that named the path (``-o``, ``--csv``, ``PATH``), for the message.
    path : str
        The path as given.

    Returns
    -------
    str or None
        The kind of an existing device or FIFO that will be written into, else None (a
        regular file, new or to be replaced).

    Raises
    ------
    InputError
        Naming the option and the path: a symbolic link, a missing folder, a folder, a block
        device or socket, a read-only file or folder, a name the file system cannot hold.
    """
    _check_path_form(flag, path)
    kind = special_file(path)
    if kind == "symbolic link":
        raise InputError(flag, path, _link_refusal(path))
    if kind in WRITE_THROUGH:
        return kind  # /dev/null, a FIFO: written into, nothing is created beside it
    if kind == "folder":
        raise InputError(flag, path, "a file path, not an existing folder")
    if kind is not None:
        raise InputError(flag, path, f"a file path or a character device (this is a {kind})")
    planted = planted_link(path)
    if planted is not None:
        raise InputError(
            flag,
            path,
            f"a path that does not go through {planted} (a link another user owns in a shared "
            "folder)",
        )
    missing, parent = _missing_folder(path)
    if not os.path.isdir(parent):
        raise InputError(
            flag, path, f"a writable path (cannot write inside {parent}: not a folder)"
        )
    if missing is not None:
        raise InputError(
            flag,
            path,
            f"a path in an existing folder ({missing} does not exist; no folder is made)",
        )
    if os.path.exists(path) and not os.access(path, os.W_OK):
        raise InputError(flag, path, "a writable file (cannot write: this one is read-only)")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(flag, path, f"a writable path (cannot write in the folder {parent})")
    _probe_folder(flag, path, parent)
    return None


def _check_path_form(flag: str, path: str) -> None:
    """A path that names a file: no trailing separator, every component a name the file
    system can hold (at most NAME_MAX bytes), no NUL."""
    if not path.strip():
        raise InputError(flag, path, "a file path")
    if "\x00" in path:
        raise InputError(flag, path, "a file path without NUL characters")
    seps = (os.sep, os.altsep) if os.altsep else (os.sep,)
    if path.endswith(seps):
        raise InputError(flag, path, "a file path, not a folder (it ends in a path separator)")
    for part in path.replace(os.altsep or os.sep, os.sep).split(os.sep):
        size = len(os.fsencode(part))
        if size > NAME_MAX:
            raise InputError(
                flag,
                path,
                f"file and folder names of at most {NAME_MAX} bytes (one has {size})",
            )


def _probe_folder(flag: str, path: str, folder: str) -> None:
    """Create and remove a nameless file in ``folder``: what a write will need (read-only file
    systems, /proc, a full quota answer here, not after the computation)."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise InputError(
            flag, path, f"a writable path (creating a file in {folder} fails: {exc.strerror})"
        ) from None


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _keep_owner_and_mode(fd: int, p: Path) -> None:
    """Give the staged file ``fd`` what the file it replaces had: owner and group where this
    process may set them, and the permission bits (set-user-ID, set-group-ID and sticky bits
    are not carried to rewritten data). A new file gets ``0666`` less the umask."""
    try:
        old = os.lstat(p)
    except OSError:
        old = None
    if old is None or not stat.S_ISREG(old.st_mode):
        os.fchmod(fd, 0o666 & ~_umask())
        return
    if (old.st_uid, old.st_gid) != (os.geteuid(), os.getegid()):
        for uid, gid in ((old.st_uid, old.st_gid), (-1, old.st_gid)):
            try:
                os.fchown(fd, uid, gid)
                break
            except OSError:
                continue
    os.fchmod(fd, stat.S_IMODE(old.st_mode) & 0o777)


def _stage(p: Path, data: bytes) -> str:
    """Write ``data`` to a new temporary file beside ``p`` (same folder, never created) and
    return its name, with the owner and mode ``p`` will keep.

    On Linux the bytes go to an anonymous ``O_TMPFILE`` first and get a name only once they are
    all written, so a process killed mid-write leaves nothing behind; elsewhere ``mkstemp``.
    """
    folder = p.parent
    # the temporary name must fit the file system's 255-byte limit however long the target's is
    stem = os.fsencode(p.name)[:200].decode("utf-8", "ignore") or "out"
    flag = getattr(os, "O_TMPFILE", 0)
    if flag and os.path.isdir("/proc/self/fd"):
        try:
            fd = os.open(folder, flag | os.O_WRONLY, 0o600)
        except OSError:
            fd = -1
        if fd >= 0:
            try:
                _write_all(fd, data)
                _keep_owner_and_mode(fd, p)
                for _ in range(100):
                    tmp = os.path.join(folder, f".{stem}.{os.urandom(4).hex()}.part")
                    try:
                        os.link(f"/proc/self/fd/{fd}", tmp, follow_symlinks=True)
                        return tmp
                    except FileExistsError:
                        continue
            except OSError:
                pass
            finally:
                os.close(fd)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{stem}.", suffix=".part")
    try:
        try:
            _write_all(fd, data)
            _keep_owner_and_mode(fd, p)
        finally:
            os.close(fd)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return tmp


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def _write_through(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` into an existing character device or FIFO (``/dev/null``, a pipe a reader
    holds open). A FIFO nobody reads is an error, not a hang; a full device (``/dev/full``) too.
    A link is followed only if it is a system stream link (the path may have changed since it
    was checked)."""
    flags = os.O_WRONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0)
    if not _stream_link(path):
        flags |= getattr(os, "O_NOFOLLOW", 0)
    fd = os.open(path, flags)
    try:
        if _kind(os.fstat(fd).st_mode) not in WRITE_THROUGH:
            raise OSError(errno.EINVAL, "no longer a device or FIFO")
        os.set_blocking(fd, True)
        _write_all(fd, data)
    finally:
        os.close(fd)


def _stage_one(given: Any, data: bytes) -> str:
    """Stage the file for ``given`` (a path that is new or a regular file); DataError if it
    has become something else since it was checked."""
    kind = special_file(given)
    if kind == "symbolic link":
        raise DataError(f"{given}: a symbolic link; outputs are not written through links")
    if kind is not None:
        raise DataError(f"{given}: cannot write into a {kind} (a regular file is needed)")
    p = Path(given)
    planted = planted_link(p)
    if planted is not None:
        raise DataError(f"{given}: not written through {planted}, a link another user owns")
    if not p.parent.is_dir():
        why = "does not exist; no folder is made" if not p.parent.exists() else "is not a folder"
        raise DataError(f"{given}: cannot write here ({p.parent} {why})")
    try:
        return _stage(p, data)
    except OSError as exc:
        raise DataError(f"{given}: cannot write here ({exc.strerror or exc})") from None


def write_files_atomic(files: Mapping[Any, str | bytes]) -> list[Path]:
    """Write several files all or nothing: each staged beside its path, then all renamed.

    Each staged file is renamed onto the path as given, never onto a resolved target; a path
    that is a symbolic link is refused, and no folder is created. An existing regular file
    keeps its permission bits (and owner and group where the process may set them); a new file
    gets ``0666`` less the umask. An existing character device or FIFO (``-o /dev/null``) is
    written into, never replaced by a file; a block device, socket or folder is refused. If any
    file cannot be staged or any device written, no file is written and every temporary file
    is removed (the devices are written after every file is staged, and before any is renamed
    into place).

    Parameters
    ----------
    files : mapping of path to str or bytes
        Each output path and its content (text is written as UTF-8).

    Returns
    -------
    list of Path
        The paths, in the order given.

    Raises
    ------
    DataError
        A folder is missing, a path is a link, a file or device cannot be written (a full disk,
        a FIFO with no reader), or a path is neither a regular file nor a device one can write
        into (one line, exit 2).
    """
    from spiralcap import stopping

    stopping.raise_if_requested()  # a stop request that came before: nothing is staged
    refuse_inputs(files)
    staged: list[tuple[str, Any]] = []
    devices: list[tuple[Any, bytes]] = []
    try:
        with stopping.deferred():  # a stop waits for the staged names, removed below
            for given, text in files.items():
                # a file name of bytes that are not UTF-8 (held as surrogates) is written as "?"
                data = text.encode("utf-8", "replace") if isinstance(text, str) else text
                if special_file(given) in WRITE_THROUGH:
                    devices.append((given, data))
                else:
                    staged.append((_stage_one(given, data), given))
        with stopping.committing():  # a stop before: nothing written; from here: all of it
            _commit(devices, staged)
    finally:
        with stopping.deferred():  # every staged name removed, whatever comes meanwhile
            for tmp, _ in staged:
                Path(tmp).unlink(missing_ok=True)
    return [Path(g) for g in files]


def _commit(devices: list[tuple[Any, bytes]], staged: list[tuple[str, Any]]) -> None:
    """Write into the devices, then rename each staged file onto its path."""
    for given, data in devices:
        try:
            _write_through(given, data)
        except OSError as exc:
            why = exc.strerror or str(exc)
            if exc.errno == errno.ENXIO:
                why = "a FIFO that nobody reads"
            raise DataError(f"{given}: cannot write ({why})") from None
    for tmp, given in staged:
        try:
            os.replace(tmp, given)  # onto the name itself: a link there is replaced
        except OSError as exc:
            raise DataError(f"{given}: cannot write ({exc.strerror or exc})") from None


def write_text_atomic(path: str | os.PathLike[str], text: str | bytes) -> Path:
    """Write one file all at once (:func:`write_files_atomic`): staged beside it, renamed onto
    the path itself; no folder is made, a link is refused, an existing file keeps its mode.

    Parameters
    ----------
    path : str or path-like
        The output path.
    text : str or bytes
        The content (text is written as UTF-8).

    Raises
    ------
    DataError
        The folder is missing or the file cannot be written (one line, exit 2).
    """
    return write_files_atomic({path: text})[0]


# --- inputs are never outputs (issue 39) ---


class _RunFiles:
    """The files one command run reads and writes, by identity: the resolved path (symbolic
    links, ``./`` and ``..`` resolved) and, for an existing file, its device and inode (hard
    links)."""

    def __init__(self) -> None:
        #: (resolved path or (device, inode)) -> (the path as named, what it is)
        self.inputs: dict[Any, tuple[str, str]] = {}
        #: (resolved path or (device, inode)) -> (the option, the path as given)
        self.outputs: dict[Any, tuple[str, str]] = {}


_RUN: list[_RunFiles | None] = [None]


@contextlib.contextmanager
def run_files() -> Iterator[None]:
    """The block of one command run (:func:`spiralcap.cli.main`): every file it reads
    (:func:`note_input`) is refused as an output (:func:`note_output`, and again at the commit in
    :func:`write_files_atomic`). Outside it (library use) nothing is recorded."""
    before = _RUN[0]
    _RUN[0] = _RunFiles()
    try:
        yield
    finally:
        _RUN[0] = before


def _identities(path: str | os.PathLike[str], st: os.stat_result | None = None) -> list[Any]:
    """What names the file ``path`` whatever alias reaches it: its resolved path and, if it is
    an existing regular file, ``(device, inode)``."""
    ids: list[Any] = [os.path.realpath(path)]
    if st is None:
        try:
            st = os.stat(path)
        except (OSError, ValueError):
            st = None
    if st is not None and stat.S_ISREG(st.st_mode):
        ids.append((st.st_dev, st.st_ino))
    return ids


def note_input(path: str | os.PathLike[str], what: str, st: os.stat_result | None = None) -> None:
    """Record ``path`` as an input of this run (a design file, a file a design names, bench
    data), described by ``what``; ``st`` is its ``fstat`` where the caller has it.

    Raises
    ------
    InputError
        Naming the option of an output already given that is this same file.
    """
    run = _RUN[0]
    if run is None:
        return
    for ident in _identities(path, st):
        run.inputs.setdefault(ident, (os.fspath(path), what))
        if ident in run.outputs:
            flag, given = run.outputs[ident]
            raise InputError(flag, given, _not_an_input(path, what))


def note_output(flag: str, path: str | os.PathLike[str]) -> None:
    """Record ``path`` (given with option ``flag``) as an output of this run.

    Raises
    ------
    InputError
        Naming ``flag``: the path is a file this run reads.
    """
    run = _RUN[0]
    if run is None:
        return
    for ident in _identities(path):
        if ident in run.inputs:
            raise InputError(flag, os.fspath(path), _not_an_input(*run.inputs[ident]))
        run.outputs.setdefault(ident, (flag, os.fspath(path)))


def refuse_inputs(files: Mapping[Any, Any]) -> None:
    """At the commit: none of the paths of ``files`` may be a file this run read or named
    (InputError naming the option the path was given with, or ``output``)."""
    run = _RUN[0]
    if run is None:
        return
    for given in files:
        for ident in _identities(given):
            if ident in run.inputs:
                flag = next(
                    (f for i in _identities(given) for f, _ in [run.outputs.get(i, ("", ""))] if f),
                    "output",
                )
                raise InputError(flag, os.fspath(given), _not_an_input(*run.inputs[ident]))


def _not_an_input(path: str | os.PathLike[str], what: str) -> str:
    return f"a file other than {os.fspath(path)} ({what}; inputs are never overwritten)"
