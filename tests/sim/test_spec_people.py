"""What the scenario spec says about a person reaches the simulator: `people.<human>.speed` is that person's
walking speed (HuNavSim's max_vel); unset, bodies.PERSON_MAX_SPEED."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from socnavgen.bodies import PERSON_MAX_SPEED
from socnavgen.cards.generate import write_card_run
from socnavgen.sim import simulate_run

WAREHOUSE = Path(__file__).resolve().parents[2] / "examples" / "locations" / "warehouse"


def top_speed(run: Path) -> float:
    trace = simulate_run(run, timeout=20.0, save=False)
    return float(np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4]).max())


def test_a_persons_speed_in_the_spec_is_their_walking_speed(tmp_path: Path) -> None:
    run = write_card_run("frontal-approach", WAREHOUSE, tmp_path / "run").root
    default = top_speed(run)
    assert default > 0.6 and default <= PERSON_MAX_SPEED + 1e-9
    spec = json.loads((run / "spec.json").read_text())
    spec["people"] = {"human1": {"speed": 0.4}}  # a resident with a cane
    (run / "spec.json").write_text(json.dumps(spec))
    assert 0.3 < top_speed(run) <= 0.4 + 1e-9
