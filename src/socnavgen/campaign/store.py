"""The episode table on disk, resumable after `kill -9`.

Finished rows are flushed in small Parquet part files (OUT/parts/part-*.parquet), each written to a temp
file and renamed, so a kill never leaves a half file: what is on disk is complete and counts as done, what
was in flight is simply run again. `episodes.parquet` is the consolidated table (sorted by scenario, policy,
seed, so any executor produces the very same file content) written at the end of every run."""

from __future__ import annotations

import io
import os
import time
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from socnavgen.campaign.columns import schema
from socnavgen.safeio import atomic_write_bytes

PARTS = "parts"
TABLE = "episodes.parquet"
SORT = [("scenario", "ascending"), ("policy", "ascending"), ("seed", "ascending")]


class EpisodeStore:
    def __init__(self, out: Path, metrics: list[str] | tuple[str, ...] | None = None,
                 flush_rows: int = 32, flush_seconds: float = 2.0) -> None:
        self.out = Path(out)
        self.schema = schema(metrics)
        self.flush_rows, self.flush_seconds = flush_rows, flush_seconds
        self._pending: list[dict[str, Any]] = []
        self._last_flush = time.monotonic()
        (self.out / PARTS).mkdir(parents=True, exist_ok=True)

    def part_files(self) -> list[Path]:
        return sorted((self.out / PARTS).glob("part-*.parquet"))

    def read_parts(self) -> pa.Table:
        files = self.part_files()
        if not files:
            return self.schema.empty_table()
        tables = [pq.read_table(f) for f in files]
        return pa.concat_tables([t.select(self.schema.names).cast(self.schema) for t in tables])

    def done_keys(self) -> set[str]:
        return set(self.read_parts().column("episode").to_pylist())

    def add(self, row: dict[str, Any]) -> None:
        self._pending.append(row)
        if len(self._pending) >= self.flush_rows or time.monotonic() - self._last_flush >= self.flush_seconds:
            self.flush()

    def flush(self) -> None:
        self._last_flush = time.monotonic()
        if not self._pending:
            return
        table = pa.Table.from_pylist(self._pending, schema=self.schema)
        buf = io.BytesIO()
        pq.write_table(table, buf)
        name = f"part-{time.time_ns():020d}-{os.getpid()}.parquet"
        atomic_write_bytes(self.out / PARTS / name, buf.getvalue())
        self._pending.clear()

    def consolidate(self) -> pa.Table:
        """episodes.parquet from every part (first row of an episode wins; none are duplicated)."""
        self.flush()
        table = self.read_parts()
        keys = table.column("episode").to_pylist()
        seen: set[str] = set()
        keep = [i for i, k in enumerate(keys) if not (k in seen or seen.add(k))]
        table = table.take(pa.array(keep, type=pa.int64())).sort_by(SORT)
        buf = io.BytesIO()
        pq.write_table(table, buf)
        atomic_write_bytes(self.out / TABLE, buf.getvalue())
        return table


def read_episodes(out: Path) -> pa.Table:
    """The campaign's table (episodes.parquet, else the parts of an unfinished run)."""
    out = Path(out)
    if (out / TABLE).is_file():
        return pq.read_table(out / TABLE)
    files = sorted((out / PARTS).glob("part-*.parquet"))
    if not files:
        from socnavgen.errors import InputFileError

        raise InputFileError("no episodes in this folder", file=out, hint="run `socnavgen campaign run FILE -o OUT`")
    return pa.concat_tables([pq.read_table(f) for f in files], promote_options="default")
