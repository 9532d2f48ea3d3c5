"""The Gymnasium environment passes gymnasium's checker and runs a campaign's scenarios."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from socnavgen.campaign.gym_env import SocNavEnv
from socnavgen.campaign.runner import run_campaign


def _toward_goal(obs: dict) -> dict:
    g = obs["goal"]
    return {"velocity": (0.8 * g / max(float(np.hypot(*g)), 1e-6)).astype(np.float32), "gesture": 0}


def test_env_checker_and_an_episode(small_spec, tmp_path) -> None:  # noqa: ANN001
    run_campaign(small_spec.model_copy(update={"seeds": [0], "policies": small_spec.policies[:1]}),
                 tmp_path / "o", executor="inline")
    env = SocNavEnv(tmp_path / "o", max_people=4, timeout=30.0)
    check_env(env, skip_render_check=True)
    a, _ = env.reset(seed=7)
    b, info = env.reset(seed=7)
    assert all(np.array_equal(a[k], b[k]) for k in a)
    assert env.observation_space.contains(a) and a["people_mask"].sum() >= 1
    start = float(np.hypot(*a["goal"]))
    obs, total, steps = a, 0.0, 0
    done = False
    while not done:
        obs, reward, terminated, truncated, _ = env.step(_toward_goal(obs))
        total, steps, done = total + reward, steps + 1, terminated or truncated
    assert steps <= 30.0 / 0.05 + 1
    assert float(np.hypot(*obs["goal"])) < start  # the action moved the robot toward its goal
    assert info["scenario"].endswith(("blind-corner", "intersection-no-gesture"))
    # the range scan and the route ahead (robot.sensors; tested on a small map in tests/sim/test_sensors.py)
    assert a["scan"].shape == (64,) and 0.0 < a["scan"].min() <= a["scan"].max() <= 8.0
    assert a["route"].shape == (8, 2) and abs(float(np.hypot(*a["route"][0])) - 0.5) < 0.1
    assert np.allclose(np.hypot(*np.diff(a["route"], axis=0).T)[:3], 0.5, atol=0.1)

    # actions outside the action space are refused with what is wrong, and leave the simulation as it was
    env.reset(seed=1)
    t = env.sim.t
    bad = [{"velocity": np.zeros(3, np.float32), "gesture": 0}, {"velocity": [[0.1, 0.2]], "gesture": 0},
           {"velocity": [np.nan, 0.0], "gesture": 0}, {"velocity": "fast", "gesture": 0}, {"velocity": [0.1, 0.2]},
           *({"velocity": np.zeros(2, np.float32), "gesture": g} for g in (99, -3, 10**40, 2.5, True))]
    for action in bad:
        with pytest.raises(ValueError, match="action"):
            env.step(action)
    assert env.sim.t == t
    obs, *_ = env.step({"velocity": np.zeros(2, np.float32), "gesture": np.int64(4)})
    assert env.sim.robot.gesture == 4 and env.sim.t > t


def test_the_unicycle_action_and_fewer_observations(small_spec, tmp_path) -> None:  # noqa: ANN001
    run_campaign(small_spec.model_copy(update={"seeds": [0], "policies": small_spec.policies[:1],
                                               "scenarios": small_spec.scenarios[:1]}), tmp_path / "o",
                 executor="inline")
    env = SocNavEnv(tmp_path / "o", max_people=2, timeout=10.0, action="unicycle", scan_beams=0, route_points=0)
    obs, _ = env.reset(seed=3)
    assert "scan" not in obs and "route" not in obs and env.observation_space.contains(obs)
    assert env.action_space["unicycle"].high[1] == pytest.approx(env.body.max_omega)
    yaw0 = float(obs["robot"][2])
    for _ in range(10):  # turning on the spot, counter-clockwise
        obs, *_ = env.step({"unicycle": np.array([0.0, 1.0], np.float32), "gesture": 0})
    turned = (float(obs["robot"][2]) - yaw0 + np.pi) % (2 * np.pi) - np.pi
    assert 0.2 < turned < 0.6 and float(np.hypot(*obs["robot"][3:5])) < 1e-6
    start, yaw = obs["robot"][:2].copy(), float(obs["robot"][2])
    for _ in range(10):  # then forward: along its heading
        obs, *_ = env.step({"unicycle": np.array([0.5, 0.0], np.float32), "gesture": 0})
    moved = obs["robot"][:2] - start
    assert float(np.hypot(*moved)) > 0.05 and np.dot(moved, [np.cos(yaw), np.sin(yaw)]) > 0.95 * np.hypot(*moved)
    with pytest.raises(ValueError, match="unicycle"):
        env.step({"velocity": np.zeros(2, np.float32), "gesture": 0})
    with pytest.raises(ValueError, match="action"):
        SocNavEnv(tmp_path / "o", action="holonomic")  # type: ignore[arg-type]
