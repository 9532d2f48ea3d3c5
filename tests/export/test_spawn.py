"""People who start at one node are spread in the export exactly as the simulator spawns them (one function,
sim.scenario.spawn_points, the same seed), so Gazebo does not start with bodies inside each other."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from socnavgen.cards.generate import write_card_run
from socnavgen.export import export_run
from socnavgen.export.scene import build_scene
from socnavgen.sim import simulate_run

WAREHOUSE = Path(__file__).resolve().parents[2] / "examples" / "locations" / "warehouse"


@pytest.mark.parametrize("seed", [0, 5])
def test_a_group_starts_apart_where_the_simulator_spawns_it(seed: int, tmp_path: Path) -> None:
    run = write_card_run("join-group", WAREHOUSE, tmp_path / "run").root  # three people start at one node
    scene, location = build_scene(run, seed=seed)
    starts = [(h.start.x, h.start.y) for h in scene.humans]
    assert len({h.path[0] for h in scene.humans}) == 1 and len(starts) == 3
    assert min(math.dist(a, b) for a, b in itertools.combinations(starts, 2)) >= 2 * 0.4  # no overlap
    trace = simulate_run(run, location=location, seed=seed, timeout=0.05, save=False)
    np.testing.assert_allclose(trace.humans[0, :, :2], starts, atol=1e-9)  # row 0 = where they were spawned
    np.testing.assert_allclose(trace.humans[0, :, 2], [h.start.yaw for h in scene.humans], atol=1e-9)
    export_run(run, "socrates", tmp_path / "out", seed=seed)
    agents = yaml.safe_load((tmp_path / "out/hunav_agent_manager/config/custom_agents.yaml").read_text())
    params = agents["hunav_loader"]["ros__parameters"]
    poses = [(params[n]["init_pose"]["x"], params[n]["init_pose"]["y"]) for n in params["agents"]]
    np.testing.assert_allclose(poses, starts, atol=1e-4)  # yaml keeps 0.1 mm


def test_the_seed_changes_where_a_lone_walker_starts(tmp_path: Path) -> None:
    run = write_card_run("frontal-approach", WAREHOUSE, tmp_path / "run").root
    first = build_scene(run, seed=0)[0].humans[0].start
    again = build_scene(run, seed=0)[0].humans[0].start
    other = build_scene(run, seed=1)[0].humans[0].start
    assert (first.x, first.y) == (again.x, again.y) and (first.x, first.y) != (other.x, other.y)
