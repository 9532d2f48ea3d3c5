"""The episode table on disk, resumable after `kill -9`.

Finished rows are flushed in small Parquet part files (OUT/parts/part-*.parquet), each written to a temp
file and renamed, so a kill never leaves a half file: what is on disk is complete and counts as done, what
was in flight is simply run again. A part that is unreadable all the same (0 bytes, truncated by a full disk
or a copy) is named and set aside as `*.broken` (its episodes run again), never a reason to stop.

Each row carries `inputs`, the digest of what decided it (fingerprint.py): a row counts as done only for the
same inputs. `episodes.parquet` is the consolidated table of the campaign's current episodes (sorted by
scenario, policy, seed, so any executor produces the very same file content); it exists only while the
campaign is finished: a run with work to do removes it first and writes it at the end."""

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
TRAJECTORIES = "trajectories"  # OUT/trajectories/<policy>/<scenario>/<seed>.npz (sim/outputs/trajectory.py)
BROKEN = ".broken"
SORT = [("scenario", "ascending"), ("policy", "ascending"), ("seed", "ascending")]


def read_parquet(path: Path) -> pa.Table | None:
    """The table in `path`, or None when it is not a whole Parquet file (empty, truncated, garbage)."""
    try:
        return pq.read_table(path)
    except (pa.ArrowException, OSError, ValueError):
        return None


class EpisodeStore:
    def __init__(self, out: Path, metrics: list[str] | tuple[str, ...] | None = None,
                 flush_rows: int = 32, flush_seconds: float = 2.0) -> None:
        self.out = Path(out)
        self.schema = schema(metrics)
        self.flush_rows, self.flush_seconds = flush_rows, flush_seconds
        self._pending: list[dict[str, Any]] = []
        self._last_flush = time.monotonic()
        self.problems: list[str] = []  # parts found unreadable and set aside
        (self.out / PARTS).mkdir(parents=True, exist_ok=True)

    def part_files(self) -> list[Path]:
        return sorted((self.out / PARTS).glob("part-*.parquet"))

    def read_parts(self) -> pa.Table:
        """Every whole part, in this campaign's schema (columns a part lacks are null); an unreadable part is
        renamed `*.broken` and named in `problems`."""
        tables = []
        for f in self.part_files():
            table = read_parquet(f)
            if table is None:
                os.replace(f, f.with_name(f.name + BROKEN))
                self.problems.append(f"{f} was unreadable (empty or truncated): set aside as {f.name}{BROKEN}; "
                                     "its episodes run again")
                continue
            tables.append(_conform(table, self.schema))
        return pa.concat_tables(tables) if tables else self.schema.empty_table()

    def done(self) -> tuple[set[tuple[str, str | None]], dict[str, str | None]]:
        """((episode key, inputs digest) of every row on disk, episode key -> inputs of its latest row)."""
        table = self.read_parts()  # parts are named by time: in the order they were written
        pairs = list(zip(table.column("episode").to_pylist(), table.column("inputs").to_pylist(), strict=True))
        return set(pairs), dict(pairs)

    def add(self, row: dict[str, Any]) -> None:
        from socnavgen.campaign.episode import TRAJECTORY_BYTES

        data = row.pop(TRAJECTORY_BYTES, None)
        if data is not None:  # written here, by the one process that owns the folder, whatever the executor
            relative = trajectory_path(row["scenario"], row["policy"], int(row["seed"]))
            atomic_write_bytes(self.out / relative, data)
            row["trajectory"] = relative
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

    def unfinish(self) -> None:
        """The campaign has work to do: its consolidated table (ours) goes until the work is done."""
        (self.out / TABLE).unlink(missing_ok=True)

    def consolidate(self, plan: dict[str, str] | None = None) -> pa.Table:
        """episodes.parquet from the parts: one row per episode of `plan` (key -> inputs digest; the first
        row with those inputs wins), or per episode key when no plan is given."""
        self.flush()
        table = select_rows(self.read_parts(), plan)
        buf = io.BytesIO()
        pq.write_table(table, buf)
        atomic_write_bytes(self.out / TABLE, buf.getvalue())
        return table


def _slug(text: str) -> str:
    """A file-name-safe form of a name (a short digest added when anything had to be replaced, so two names
    never share a file)."""
    import hashlib

    safe = "".join(c if c.isalnum() or c in "._-" else "_" for c in text)[:80].strip(".") or "_"
    return safe if safe == text else f"{safe}-{hashlib.sha256(text.encode()).hexdigest()[:8]}"


def trajectory_path(scenario: str, policy: str, seed: int) -> str:
    """Where an episode's trajectories go, relative to the campaign folder (POSIX separators)."""
    parts = [_slug(p) for p in scenario.split("/")]
    return "/".join([TRAJECTORIES, _slug(policy), *parts, f"{int(seed)}.npz"])


def _conform(table: pa.Table, target: pa.Schema) -> pa.Table:
    columns = [table.column(f.name).cast(f.type) if f.name in table.column_names
               else pa.nulls(table.num_rows, f.type) for f in target]
    return pa.Table.from_arrays(columns, schema=target)


def select_rows(table: pa.Table, plan: dict[str, str] | None) -> pa.Table:
    """The first row of each planned episode with its planned inputs (each key once), sorted."""
    keys = table.column("episode").to_pylist()
    inputs = table.column("inputs").to_pylist() if "inputs" in table.column_names else [None] * len(keys)
    seen: set[str] = set()
    keep = []
    for i, (key, digest) in enumerate(zip(keys, inputs, strict=True)):
        if key in seen or (plan is not None and plan.get(key, "\0") != digest):
            continue
        seen.add(key)
        keep.append(i)
    return table.take(pa.array(keep, type=pa.int64())).sort_by(SORT)


def read_episodes(out: Path, plan: dict[str, str] | None = None) -> tuple[pa.Table, list[str]]:
    """(the campaign's table, notes): episodes.parquet when it is whole, else rebuilt from the parts that are
    (read only: nothing is renamed), with a note naming every file that is not."""
    from socnavgen.errors import InputFileError

    out = Path(out)
    notes: list[str] = []
    if (out / TABLE).is_file():
        table = read_parquet(out / TABLE)
        if table is not None:
            return table, notes
        notes.append(f"{out / TABLE} is unreadable (empty or truncated): the table is rebuilt from parts/; "
                     "`socnavgen campaign run` writes it again")
    tables = []
    for f in sorted((out / PARTS).glob("part-*.parquet")):
        table = read_parquet(f)
        if table is None:
            notes.append(f"{f} is unreadable (empty or truncated) and left out; `socnavgen campaign run` runs its "
                         "episodes again")
        else:
            tables.append(table)
    if not tables:
        raise InputFileError("no episodes in this folder", file=out, hint="run `socnavgen campaign run FILE -o OUT`")
    table = pa.concat_tables(tables, promote_options="default")
    return select_rows(table, plan), notes
