"""Campaign runs: one row per episode, executors agree, failures stay in their episode, maps load once."""

from __future__ import annotations

from pathlib import Path

import duckdb
import pyarrow.parquet as pq
import pytest

from socnavgen.campaign import episode as episode_module
from socnavgen.campaign.runner import run_campaign
from socnavgen.campaign.spec import parse_campaign
from socnavgen.run.folder import RunFolder
from tests.campaign.conftest import POLICIES, campaign_yaml

VOLATILE = ["wall_seconds"]


def test_inline_and_local_processes_write_the_same_table(small_spec, tmp_path) -> None:  # noqa: ANN001
    inline = run_campaign(small_spec, tmp_path / "inline", executor="inline")
    local = run_campaign(small_spec, tmp_path / "local", executor="local", workers=2, batch_size=1)
    assert inline.total == local.total == 8 and inline.failed == local.failed == 0
    a = pq.read_table(tmp_path / "inline" / "episodes.parquet").drop(VOLATILE)
    b = pq.read_table(tmp_path / "local" / "episodes.parquet").drop(VOLATILE)
    assert a.equals(b)
    rows = duckdb.sql(f"select scenario, policy, seed, status, success, minimum_distance_to_people, verified, "
                      f"verdicts, path_efficiency from '{tmp_path / 'inline' / 'episodes.parquet'}' "
                      f"order by scenario, policy, seed").fetchall()
    assert [(r[0], r[1], r[2]) for r in rows] == [(s, p, k) for s in ("warehouse/blind-corner", "warehouse/intersection-no-gesture")
                                                  for p in ("bad", "scripted") for k in (0, 1)]
    assert all(r[3] == "ok" and r[6] is not None and r[7].startswith("[") for r in rows)
    bad = [r[5] for r in rows if r[1] == "bad"]
    good = [r[5] for r in rows if r[1] == "scripted"]
    # driving through people shows in the table: at the blind corner (nobody sees it coming) bodies overlap; at the
    # open intersection people let a robot that drives across go by (sim/people/avoid.py: off its swept way)
    assert [r[5] for r in rows if r[1] == "bad" and "blind" in r[0]] == [0.0, 0.0] and min(bad) == 0.0 < min(good)


def test_crash_and_hang_fail_their_episode_only(tmp_path) -> None:  # noqa: ANN001
    text = campaign_yaml(["blind-corner"], ["waypoints", f"{{name: crash, robot: '{POLICIES}:Crashes'}}",
                                            f"{{name: hang, robot: '{POLICIES}:Hangs'}}"], 1, wall_timeout=1.5)
    result = run_campaign(parse_campaign(text), tmp_path / "o", executor="inline")
    rows = {r["policy"]: r for r in pq.read_table(tmp_path / "o" / "episodes.parquet").to_pylist()}
    assert result.total == 3 and result.failed == 2
    assert rows["waypoints"]["status"] == "ok" and rows["waypoints"]["steps"] > 100
    assert rows["crash"]["status"] == "failed" and "ZeroDivisionError: policy bug" in rows["crash"]["failure_reason"]
    assert "policies.py" in rows["crash"]["failure_reason"]
    assert rows["hang"]["status"] == "failed" and rows["hang"]["failure_reason"].startswith("timeout")
    assert rows["crash"]["success"] is False and rows["crash"]["collisions"] is None


def test_a_worker_loads_each_location_once(small_spec, tmp_path, monkeypatch) -> None:  # noqa: ANN001
    cache = episode_module.WorkerCache()
    monkeypatch.setattr(episode_module, "WORKER_CACHE", cache)
    read = []
    original = RunFolder.read_paths
    monkeypatch.setattr(RunFolder, "read_paths", lambda self: read.append(self.root.name) or original(self))
    run_campaign(small_spec, tmp_path / "o", executor="inline")
    assert cache.loads == 1 and len(cache.worlds) == 1
    # one LoadedRun per scenario, shared by its 4 episodes' simulations and verifications: paths.json read once
    assert sorted(Path(r).name for r in cache.runs) == ["blind-corner", "intersection-no-gesture"]
    assert sorted(read[-2:]) == ["blind-corner", "intersection-no-gesture"] and len(read) == 4  # 2 while building the suite


def test_metric_selection_and_definitions(tmp_path) -> None:  # noqa: ANN001
    text = campaign_yaml(["blind-corner"], ["waypoints"], 1) + "metrics: [collisions, path_irregularity]\n"
    run_campaign(parse_campaign(text), tmp_path / "o", executor="inline")
    table = pq.read_table(tmp_path / "o" / "episodes.parquet")
    assert {"success", "collisions", "path_irregularity"} <= set(table.column_names)
    assert "social_work" not in table.column_names
    import json

    definitions = json.loads((tmp_path / "o" / "metrics.json").read_text())
    assert set(definitions) == {"collisions", "path_irregularity"}
    assert definitions["path_irregularity"]["unit"] == "rad/m" and "yaw" in definitions["path_irregularity"]["formula"]


def test_run_folders_and_a_folder_of_runs(tmp_path) -> None:  # noqa: ANN001
    from socnavgen.cards.generate import write_card_run
    from tests.campaign.conftest import WAREHOUSE

    for card in ("blind-corner", "down-path"):
        write_card_run(card, WAREHOUSE, tmp_path / "runs" / card)
    (tmp_path / "runs" / "notes").mkdir()  # not a run: ignored by `folder:`
    file = tmp_path / "c.yaml"
    file.write_text("scenarios:\n  - folder: runs\n  - runs: [runs/blind-corner]\npolicies: [waypoints]\nseeds: 1\n"
                    "simulation: {timeout: 20}\nverify: false\n")
    from socnavgen.campaign.spec import load_campaign

    result = run_campaign(load_campaign(file), tmp_path / "out", executor="inline")
    assert [s.id for s in result.suite.scenarios] == ["blind-corner", "down-path", "blind-corner~2"]
    assert [s.source for s in result.suite.scenarios] == ["folder", "folder", "runs"]
    rows = pq.read_table(tmp_path / "out" / "episodes.parquet").to_pylist()
    assert len(rows) == 3 and all(r["card"] in ("blind-corner", "down-path") for r in rows)
    assert all(r["verified"] is None and r["verdicts"] is None for r in rows)  # verify: false
    assert {r["location"] for r in rows} == {"warehouse"}


def test_a_changed_campaign_runs_only_what_it_adds_and_another_is_refused(small_spec, tmp_path) -> None:  # noqa: ANN001
    from socnavgen.errors import InputFileError

    run_campaign(small_spec.model_copy(update={"seeds": [0]}), tmp_path / "o", executor="inline")
    more = run_campaign(small_spec.model_copy(update={"seeds": [0, 5]}), tmp_path / "o", executor="inline")
    assert (more.skipped_done, more.ran) == (4, 4)
    with pytest.raises(InputFileError, match="another campaign"):
        run_campaign(small_spec.model_copy(update={"name": "other"}), tmp_path / "o", executor="inline")


def test_compiling_the_simulator_does_not_count_against_an_episode(small_spec, tmp_path, monkeypatch) -> None:  # noqa: ANN001
    """On a new machine numba compiles the simulator in each worker's first episode (~40 s): that happens
    before the episode's wall-clock limit starts. A compile slower than the limit must not fail an episode
    (it did on a fresh clone: Ray's first episode per worker failed its 20 s limit)."""
    import time

    import socnavgen.sim

    calls = []
    real = socnavgen.sim.warm_up

    def slow_compile() -> None:
        if not calls:  # the first call compiles, as on a new machine: longer than the episodes' limit below
            time.sleep(1.5)
        calls.append(1)
        real()

    monkeypatch.setattr(socnavgen.sim, "warm_up", slow_compile)
    spec = small_spec.model_copy(update={"seeds": [0], "simulation": small_spec.simulation.model_copy(
        update={"wall_timeout": 1.0})})
    result = run_campaign(spec, tmp_path / "o", executor="inline")
    assert len(calls) == 5 and result.failed == 0 and result.ran == 4  # in the parent, then before every episode


def test_a_wall_contact_on_the_way_is_no_success_and_says_so(small_spec, tmp_path, monkeypatch) -> None:  # noqa: ANN001
    """The row of an episode whose robot reached its goal touching nobody but a wall: `success` False (it is the
    report's contact-free success), `reached_goal` True, and the failure reason names the wall."""
    from socnavgen.sim import metrics as sim_metrics

    measured = sim_metrics.navigation_metrics

    def scraped(trace, world):  # noqa: ANN001, ANN202 - the real metrics, with the robot's body once on a wall
        out = measured(trace, world)
        out.update(static_obstacle_collisions=1, min_obstacle_clearance=-0.04)
        return out

    monkeypatch.setattr(sim_metrics, "navigation_metrics", scraped)
    spec = parse_campaign(campaign_yaml(["intersection-no-gesture"], ["scripted"], 1, timeout=150.0, wall_timeout=120.0))
    run_campaign(spec, tmp_path / "c", executor="inline")
    (row,) = pq.read_table(tmp_path / "c" / "episodes.parquet").to_pylist()
    assert row["reached_goal"] and row["collisions"] == 0, (row["end_reason"], row["failure_reason"])
    assert row["success"] is False and row["time_to_goal"] is None
    assert "touched a wall (1 time, -0.04 m at the closest)" in row["failure_reason"]
