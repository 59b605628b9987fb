"""Where results go: the one rule for output paths of every command line, and atomic writing.

The rule, the same for ``python -m stickslip run --out``, ``python -m cases.*`` and
``python -m benchmarks`` (their ``--outdir``): missing directories are created (with their
parents); a path that cannot be written is refused at once, before any work, with the path
and the reason (permissions, a read-only or virtual file system, a file in the way). Every file
is then written whole or not at all (`atomic_write`: a temporary file beside it, renamed over
it once complete).
"""
from __future__ import annotations

import os
import secrets
import tempfile
from pathlib import Path
from typing import Any, Callable

__all__ = ["output_problem", "atomic_write"]


def output_problem(path: str | os.PathLike[str], *, directory: bool) -> str | None:
    """Why results cannot be written at `path`, or None when they can.

    Parameters
    ----------
    path : str or path-like
        An output directory (`directory` True) or an output file (False).
    directory : bool
        True: `path` is a directory, created with its parents if missing. False: `path` is a
        file, whose directory is created with its parents if missing; `path` must not be a
        directory.

    Returns
    -------
    str or None
        "cannot write into <dir>: <reason>" (or "<path> is a directory"), or None. Checked by
        creating and removing a file in the directory, so that permissions, read-only file
        systems and a file in the way are all found before any work starts.
    """
    path = Path(path)
    if not directory and path.is_dir():
        return f"{path} is a directory, not a file"
    folder = path if directory else (path.parent if str(path.parent) else Path("."))
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".write-test-", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        return f"cannot write into {folder}: {exc.strerror or exc}"
    return None


def atomic_write(path: str | os.PathLike[str], write: Callable[[Any], None], *,
                 binary: bool = False) -> Path:
    """Call `write(fileobj)` on a temporary file beside `path`, then `os.replace` it onto
    `path`; on any exception the temporary file is removed and `path` is left untouched.

    The file gets the permissions of any new file (0666 less the user's umask), not mkstemp's
    0600; its directory is created if missing. Text files are UTF-8 with newline="" (the csv
    module's convention). Returns `path` as a Path.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    while True:
        tmp = path.parent / f".{path.name}.{secrets.token_hex(6)}.tmp"
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            break
        except FileExistsError:            # another writer drew the same name: draw again
            continue
    try:
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else
                                                        {"newline": "", "encoding": "utf-8"})) as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path
