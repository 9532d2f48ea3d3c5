"""What a seed varies (campaign/variation.py) and what a campaign keeps of each episode besides its row (its
trajectories, sim/outputs/trajectory.py)."""

from __future__ import annotations

import json

import numpy as np
import pyarrow.parquet as pq
import pytest

from socnavgen.campaign.runner import run_campaign
from socnavgen.campaign.spec import parse_campaign
from socnavgen.campaign.variation import SPEED_MEAN, SPEED_RANGE, SPEED_SD, draw_people
from socnavgen.sim.outputs.trajectory import read_trajectory, sample_steps
from tests.campaign.conftest import campaign_yaml


def test_the_draws_follow_the_documented_distributions_and_depend_only_on_scenario_seed_and_person() -> None:
    draws = [draw_people("w/card", k, ["human1", "human2"]) for k in range(3000)]
    speeds = np.array([d["human1"].speed for d in draws])
    assert speeds.mean() == pytest.approx(SPEED_MEAN, abs=0.02) and speeds.std() == pytest.approx(SPEED_SD, abs=0.02)
    assert speeds.min() >= SPEED_RANGE[0] and speeds.max() <= SPEED_RANGE[1]
    assert np.corrcoef(speeds, [d["human2"].speed for d in draws])[0, 1] == pytest.approx(0, abs=0.06)
    spaces = np.array([d["human2"].personal_space for d in draws])
    assert spaces.mean() == pytest.approx(1.0, abs=0.02)
    delays = np.array([d["human1"].start_delay for d in draws])
    assert delays.min() >= 0 and delays.max() <= 3.0 and delays.mean() == pytest.approx(0.8, abs=0.05)
    assert draw_people("w/card", 7, ["human1"])["human1"] == draws[7]["human1"]  # per person: others do not matter
    assert draws[7]["human1"] != draw_people("w/other", 7, ["human1"])["human1"]  # per scenario
    slow = draw_people("w/card", 7, ["human1"], {"human1": 0.5})["human1"].speed  # a slow resident stays slow
    assert slow == pytest.approx(0.5 * draws[7]["human1"].speed / SPEED_MEAN, abs=1e-3)


def test_each_seed_gets_its_people_the_row_records_them_and_the_trajectories_are_kept(tmp_path) -> None:  # noqa: ANN001
    """Seeds differ by more than where people spawn: each person walks at its drawn speed (never faster, and
    close to it: the person of down-path walks ahead of the robot, nobody holds it back); the row lists the draw;
    the trajectories file is beside the table."""
    text = campaign_yaml(["down-path"], ["waypoints"], 3, timeout=20.0)
    out = tmp_path / "o"
    run_campaign(parse_campaign(text), out, executor="inline")
    rows = pq.read_table(out / "episodes.parquet").to_pylist()
    speeds = []
    for row in rows:
        drawn = json.loads(row["people_traits"])["human1"]["speed"]
        assert row["mean_person_speed"] == pytest.approx(drawn)
        data = read_trajectory(out / row["trajectory"])
        walked = np.hypot(data["humans"][:, 0, 3], data["humans"][:, 0, 4])
        assert walked.max() <= drawn + 1e-3 and walked.max() >= 0.9 * drawn
        speeds.append(drawn)
        assert data["meta"]["human_names"] == ["human1"] and data["meta"]["hz"] == 10.0
        assert data["t"][-1] == pytest.approx(row["sim_seconds"], abs=1e-3)
        assert len(data["t"]) <= 10 * row["sim_seconds"] + 2  # 10 samples a second, the last step kept
        assert (out / row["trajectory"]).stat().st_size < 60_000
    assert len(set(speeds)) == 3


def test_a_campaign_without_variation_or_trajectories(tmp_path) -> None:  # noqa: ANN001
    text = campaign_yaml(["frontal-approach"], ["waypoints"], 1, timeout=10.0).replace(
        "simulation: {", "simulation: {vary_people: false, ") + "trajectories: 0\n"
    run_campaign(parse_campaign(text), tmp_path / "o", executor="inline")
    row = pq.read_table(tmp_path / "o" / "episodes.parquet").to_pylist()[0]
    assert row["people_traits"] is None and row["trajectory"] is None
    assert not (tmp_path / "o" / "trajectories").exists()


def test_sampling_keeps_one_step_per_interval_and_the_last() -> None:
    t = np.arange(0, 10.01, 0.05)
    k = sample_steps(t, 10.0)
    assert np.allclose(np.diff(t[k][:-1]), 0.1) and k[-1] == len(t) - 1
    assert list(sample_steps(t[:1], 10.0)) == [0]
