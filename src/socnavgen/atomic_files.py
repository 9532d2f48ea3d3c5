"""All-or-nothing writes of several files and of whole folders: after any failure (disk full, a
read-only file, a target that is a folder, a crash between renames) the reader sees either the old
state or the new one, never a mix.

`write_files_atomically` stages every file as a temp file beside its target, then renames them in
turn, restoring the earlier ones if a later rename fails. `replace_folder` builds a folder's new
content in a sibling temp folder and swaps it in with two renames.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from socnavgen.errors import InputFileError
from socnavgen.safeio import atomic_write_bytes, ordinary_mode

EXPORT_MARKER = ".socnavgen-export"  # names a folder socnavgen wrote, so a re-export may replace it


def _stage(path: Path, data: bytes) -> Path:
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, ordinary_mode())  # mkstemp's 0600 would make the saved files private
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
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


def replace_folder(out: Path, fill: Callable[[Path], None], *, force: bool = False) -> None:
    """Build the new content of `out` with `fill(temp_folder)`, then swap it in whole.

    An existing `out` is replaced only when it is empty, was written by socnavgen (EXPORT_MARKER),
    or `force` is given; so a user's folder is never mixed with ours, and no stale file of an
    earlier export survives."""
    out = Path(out)
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise InputFileError("the output path exists and is not a folder", file=out, hint="choose a folder with -o")
    if out.is_dir() and any(out.iterdir()) and not (out / EXPORT_MARKER).is_file() and not force:
        raise InputFileError("the output folder is not empty and was not written by socnavgen export", file=out,
                             hint="choose a new or empty folder, or pass --force to replace its content")
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.new.", dir=out.parent))
    try:
        fill(staging)
        atomic_write_bytes(staging / EXPORT_MARKER, b"written by socnavgen export; replaced whole on re-export\n")
        os.chmod(staging, 0o777 & ~_umask())
        if out.is_dir():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old.", dir=out.parent))
            os.replace(out, old / "content")
            try:
                os.replace(staging, out)
            except BaseException:
                os.replace(old / "content", out)
                raise
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(staging, out)
    finally:
        if staging.exists():
            shutil.rmtree(staging, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
