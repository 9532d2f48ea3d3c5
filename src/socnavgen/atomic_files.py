"""All-or-nothing writes of several files: after any failure (disk full, a read-only file, a target that
is a folder, a crash between renames) the reader sees either the old state or the new one, never a mix.

`write_files_atomically` stages every file as a temp file beside its target, then renames them in
turn, restoring the earlier ones if a later rename fails.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from socnavgen.errors import InputFileError

EXPORT_MARKER = ".socnavgen-export"  # lists what an export wrote in its folder, so a re-export replaces only that


def _stage(path: Path, data: bytes) -> Path:
    """A temp file beside `path` holding `data`, with the mode `path` has (an ordinary file's, 0666 minus the
    umask, when it is new: mkstemp's 0600 would hide exports from a ROS container running as another user)."""
    mode = path.stat().st_mode & 0o777 if path.is_file() else 0o666 & ~_umask()
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, mode)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return Path(tmp)


def write_files_atomically(files: dict[Path, bytes]) -> None:
    """Replace every file of `files` or none of them."""
    targets = {Path(p): data for p, data in files.items()}
    for path in targets:
        if path.is_dir():
            raise InputFileError("cannot write this file: a folder of that name is in the way", file=path,
                                 hint="move the folder away, then try again")
    staged: dict[Path, Path] = {}
    backups: dict[Path, Path | None] = {}
    try:
        for path, data in targets.items():
            path.parent.mkdir(parents=True, exist_ok=True)
            staged[path] = _stage(path, data)
        for path in targets:
            backups[path] = _stage(path, path.read_bytes()) if path.is_file() else None
            os.replace(staged[path], path)
            del staged[path]
    except BaseException:
        for path, backup in backups.items():  # undo the renames already done
            try:
                if backup is not None:
                    os.replace(backup, path)
                elif path not in staged:
                    path.unlink(missing_ok=True)
            except OSError:
                pass
        for tmp in staged.values():
            tmp.unlink(missing_ok=True)
        raise
    for backup in backups.values():
        if backup is not None:
            backup.unlink(missing_ok=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
