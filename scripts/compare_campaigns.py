"""Are two campaigns' episode tables the same? Every column of every episode compared with DuckDB, except
wall_seconds (time) and inputs (the digest of the code and files that made the row, which changes with the
code). For checking that a speed change changed no result: run the same campaign before and after, then

    python scripts/compare_campaigns.py OUT_BEFORE OUT_AFTER

prints the rows and the columns that differ (exit code 1 if any), else that every compared column is equal."""

from __future__ import annotations

import sys
from pathlib import Path

import duckdb

IGNORED = ("wall_seconds", "inputs")


def compare(before: Path, after: Path) -> dict[str, int]:
    """Column -> how many episodes differ in it (episodes matched on their key; a missing episode counts in
    every column)."""
    con = duckdb.connect()
    a, b = (str(Path(p) / "episodes.parquet") for p in (before, after))
    columns = [r[0] for r in con.execute("DESCRIBE SELECT * FROM read_parquet(?)", [a]).fetchall()]
    compared = [c for c in columns if c not in IGNORED and c != "episode"]
    differ = ", ".join(f'count(*) FILTER (WHERE a."{c}" IS DISTINCT FROM b."{c}") AS "{c}"' for c in compared)
    row = con.execute(f"SELECT {differ} FROM read_parquet(?) a FULL JOIN read_parquet(?) b USING (episode)",
                      [a, b]).fetchone()
    counts = dict(zip(compared, row, strict=True))
    total = con.execute("SELECT count(*) FROM read_parquet(?) a FULL JOIN read_parquet(?) b USING (episode)",
                        [a, b]).fetchone()[0]
    print(f"{total} episodes, {len(compared)} columns compared (not {', '.join(IGNORED)})")
    return {c: n for c, n in counts.items() if n}


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    differ = compare(Path(sys.argv[1]), Path(sys.argv[2]))
    if differ:
        print("differ: " + ", ".join(f"{c} ({n} episodes)" for c, n in differ.items()))
        return 1
    print("every compared column is equal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
