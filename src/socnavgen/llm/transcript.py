"""The run's transcript.jsonl: one JSON line per LLM exchange, appended atomically.

Lines are written with a single `write` on an O_APPEND descriptor under a lock, so concurrent
humans in the behavior-tree stage never interleave, and a crash leaves at most one torn last line
(which `read_transcript` skips). A failed write (disk full) is cut back to the last whole line, so
a resumed run never appends after half a line.

What is stored is capped: a reply or message longer than MAX_STORED_CHARS keeps its head and a
note of the length, and once the file passes MAX_TRANSCRIPT_BYTES entries keep only their
bookkeeping (stage, tokens, error), so a runaway model cannot fill the disk.
"""

from __future__ import annotations

import json
import os
import threading
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from socnavgen.llm.redact import redact_data

MAX_STORED_CHARS = 256 * 1024  # one reply or message as stored in the transcript and the cache
MAX_TRANSCRIPT_BYTES = 64 * 1024 * 1024  # one run's transcript.jsonl
BULKY_FIELDS = ("raw", "messages", "value")


def utc_now() -> str:
    return datetime.now(UTC).isoformat(timespec="milliseconds").replace("+00:00", "Z")


class Transcript:
    def __init__(self, path: Path | None, *, max_bytes: int = MAX_TRANSCRIPT_BYTES,
                 max_chars: int = MAX_STORED_CHARS) -> None:
        self.path = Path(path) if path is not None else None
        self.max_bytes, self.max_chars = max_bytes, max_chars
        self._lock = threading.Lock()

    def append(self, entry: dict[str, Any]) -> None:
        if self.path is None:
            return
        entry = clip_texts(entry, self.max_chars)
        with self._lock:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
            try:
                start = os.fstat(fd).st_size
                if start + len(_line(entry)) > self.max_bytes:
                    entry = {k: v for k, v in entry.items() if k not in BULKY_FIELDS}
                    entry["omitted"] = f"transcript over {self.max_bytes} bytes: reply and messages not stored"
                data = _line(entry)
                try:
                    written = 0
                    while written < len(data):
                        written += os.write(fd, data[written:])
                    os.fsync(fd)
                except OSError:
                    os.ftruncate(fd, start)  # no torn line for the next append to follow
                    raise
            finally:
                os.close(fd)


def _line(entry: dict[str, Any]) -> bytes:
    return (json.dumps(redact_data(entry), ensure_ascii=False, default=str) + "\n").encode("utf-8")


def clip_text(text: str, max_chars: int) -> str:
    if len(text) <= max_chars:
        return text
    return text[:max_chars] + f"... [{len(text) - max_chars} more characters not stored]"


def clip_texts(value: Any, max_chars: int) -> Any:
    """Every string in a JSON-like value cut to `max_chars` (values were depth-checked when parsed)."""
    if isinstance(value, str):
        return clip_text(value, max_chars)
    if isinstance(value, dict):
        return {k: clip_texts(v, max_chars) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [clip_texts(v, max_chars) for v in value]
    return value


def read_transcript(path: Path) -> list[dict[str, Any]]:
    """All complete entries; a torn last line from a crash is ignored."""
    entries = []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            line = line.strip()
            if not line:
                continue
            try:
                entry = json.loads(line)
            except json.JSONDecodeError:
                continue
            if isinstance(entry, dict):
                entries.append(entry)
    return entries
