"""kill -9 in the middle of a campaign, re-run: finished episodes kept, none duplicated, none lost."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import duckdb

from tests.campaign.conftest import POLICIES, campaign_yaml

CLI = "import sys; from socnavgen.cli import main; sys.argv = ['socnavgen', *sys.argv[1:]]; main()"
REPO = Path(__file__).resolve().parents[2]


def _cli(*args: str, **kwargs) -> subprocess.Popen:  # noqa: ANN003
    env = {**os.environ, "PYTHONPATH": str(REPO / "src") + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.Popen([sys.executable, "-c", CLI, *args], env=env, cwd=REPO, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kwargs)


def test_kill_9_and_resume(tmp_path) -> None:  # noqa: ANN001
    cards = ["blind-corner", "down-path"]
    policies = ["waypoints", f"{{name: bad, robot: '{POLICIES}:StraightThrough'}}"]
    seeds = 40  # enough that the campaign is still running after its first part file (flushed every 32 rows)
    file = tmp_path / "c.yaml"
    file.write_text(campaign_yaml(cards, policies, seeds))
    out = tmp_path / "out"
    first = _cli("campaign", "run", str(file), "-o", str(out), "--workers", "2", "--batch", "1",
                 start_new_session=True)
    deadline = time.monotonic() + 120
    while not list((out / "parts").glob("part-*.parquet")) and time.monotonic() < deadline:
        assert first.poll() is None, first.communicate()
        time.sleep(0.05)
    assert first.poll() is None, "the campaign finished before it could be killed: make it longer"
    os.killpg(first.pid, signal.SIGKILL)  # the CLI and its worker processes, nothing else
    first.wait(timeout=30)
    assert first.returncode == -signal.SIGKILL
    kept = duckdb.sql(f"select count(*) from '{out}/parts/part-*.parquet'").fetchall()[0][0]
    assert 0 < kept < len(cards) * 2 * seeds
    assert not (out / "episodes.parquet").exists()

    second = _cli("campaign", "run", str(file), "-o", str(out), "--workers", "2")
    stdout, stderr = second.communicate(timeout=300)
    assert second.returncode == 0, stderr
    assert f"{kept} already done" in stdout
    table = out / "episodes.parquet"
    total, distinct = duckdb.sql(f"select count(*), count(distinct episode) from '{table}'").fetchall()[0]
    assert total == distinct == len(cards) * 2 * seeds
    combos = duckdb.sql(f"select count(distinct (scenario, policy, seed)) from '{table}' "
                        f"where status = 'ok'").fetchall()[0][0]
    assert combos == len(cards) * 2 * seeds
