"""`socnavgen campaign` as typed: the printed example runs, a worker terminated mid-episode prints no
traceback and the campaign ends, mistakes end in one message (exit 2)."""

from __future__ import annotations

import os
import subprocess
import sys

from tests.campaign.conftest import POLICIES, campaign_yaml
from tests.campaign.test_resume import CLI, REPO


def _run(*args: str, cwd=REPO, timeout: float = 120) -> subprocess.CompletedProcess:  # noqa: ANN001
    env = {**os.environ, "PYTHONPATH": str(REPO / "src") + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-c", CLI, *args], env=env, cwd=cwd, capture_output=True, text=True,
                          timeout=timeout)


def test_the_printed_example_runs_as_typed(tmp_path) -> None:  # noqa: ANN001
    """`campaign example > suite.yaml && campaign run suite.yaml` failed on a policy file the example named."""
    example = _run("campaign", "example", cwd=tmp_path)
    assert example.returncode == 0
    (tmp_path / "suite.yaml").write_text(example.stdout)
    run = _run("campaign", "run", "suite.yaml", "-o", "out", "--workers", "2", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "12 episodes (0 already done, 12 run, 0 failed)" in run.stdout
    assert "Traceback" not in run.stderr and (tmp_path / "out" / "episodes.parquet").is_file()


def test_a_worker_terminated_mid_episode_prints_no_traceback_and_the_campaign_ends(tmp_path) -> None:  # noqa: ANN001
    """The CLI's SIGTERM handler was inherited by the pool's workers: a terminated worker printed a traceback
    (8 of 12 finished campaigns printed one from Pool.terminate) and its task was lost."""
    file = tmp_path / "c.yaml"
    file.write_text(campaign_yaml(["blind-corner"], ["waypoints", f"{{name: t, robot: '{POLICIES}:TerminatedMidEpisode'}}"],
                                  1, timeout=20, wall_timeout=10))
    run = _run("campaign", "run", str(file), "-o", str(tmp_path / "out"), "--workers", "2", "--batch", "1", timeout=90)
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr and "Terminated" not in run.stderr, run.stderr
    assert "2 episodes (0 already done, 2 run, 1 failed)" in run.stdout


def test_report_of_a_missing_folder_is_one_message(tmp_path) -> None:  # noqa: ANN001
    result = _run("campaign", "report", str(tmp_path / "nope"))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "no such campaign folder" in result.stderr
