"""One writer per folder: an advisory flock on a lock file, taken without waiting (a second writer is refused
at once with one message). The kernel releases it when the process dies, so a crash never leaves a stale
lock. Used by run folders (`generate`, `simulate`) and campaign folders (`campaign run`)."""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path

from socnavgen.errors import SocnavgenError


def acquire(lock_file: Path, what: str, hint: str) -> int:
    """The descriptor holding `lock_file`'s lock (close it to release), or SocnavgenError naming the holder."""
    fd = os.open(lock_file, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = os.pread(fd, 32, 0).decode(errors="replace").strip() or "?"
        os.close(fd)
        raise SocnavgenError(f"{what} is in use by another socnavgen process (pid {holder})", hint=hint) from None
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    return fd


@contextlib.contextmanager
def held(lock_file: Path, what: str, hint: str) -> Iterator[None]:
    """`acquire` for the duration of a with-block."""
    fd = acquire(lock_file, what, hint)
    try:
        yield
    finally:
        os.close(fd)
