"""Content-addressed reply cache: the same request to the same model never costs tokens twice.

The key is the sha256 of everything that shapes a reply (backend, model, messages with image hashes,
schema, grammar, sampling parameters). Only deterministic requests (temperature 0) are cached by
default. Entries are written atomically; an unreadable entry counts as a miss. Replies longer than
MAX_STORED_CHARS are not cached (they are no stage answer), and an entry file is read only up to a
size limit.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Any

from socnavgen.llm.redact import redact_data
from socnavgen.llm.transcript import MAX_STORED_CHARS
from socnavgen.safeio import atomic_write_json, parse_json_text

MAX_ENTRY_BYTES = 8 * MAX_STORED_CHARS  # generous for escapes and metadata

CACHE_FORMAT = 1


def default_cache_dir() -> Path:
    env = os.environ.get("SOCNAVGEN_CACHE_DIR")
    if env:
        return Path(env).expanduser()
    return Path.home() / ".cache" / "socnavgen" / "llm"


def cache_key(payload: dict[str, Any]) -> str:
    canonical = json.dumps({"format": CACHE_FORMAT, **payload}, sort_keys=True, separators=(",", ":"),
                           ensure_ascii=False, default=str)
    return hashlib.sha256(canonical.encode("utf-8")).hexdigest()


class ReplyCache:
    def __init__(self, root: Path) -> None:
        self.root = Path(root)

    def _path(self, key: str) -> Path:
        return self.root / key[:2] / f"{key}.json"

    def get(self, key: str) -> dict[str, Any] | None:
        path = self._path(key)
        try:
            if path.stat().st_size > MAX_ENTRY_BYTES:
                return None
            entry = parse_json_text(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if not isinstance(entry, dict) or entry.get("key") != key or not isinstance(entry.get("raw"), str):
            return None
        return entry

    def put(self, key: str, entry: dict[str, Any]) -> None:
        if len(str(entry.get("raw", ""))) > MAX_STORED_CHARS:
            return
        atomic_write_json(self._path(key), redact_data({**entry, "key": key}))
