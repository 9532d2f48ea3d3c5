"""What a seed varies: per episode, each person's preferred walking speed, personal-space preference and start
delay are drawn from distributions measured on pedestrians, from the episode's seed (the same seed gives the
same people, whatever the policy: paired comparisons compare like with like), on top of the spawn jitter the
simulator draws from the same seed (a point within 1.5 m of the person's first node).

Distributions (DISTRIBUTIONS, shown by the report):
- preferred walking speed ~ Normal(1.34, 0.26) m/s, clipped to [0.5, 1.8]: the free walking speed of
  pedestrians (Weidmann 1993, "Transporttechnik der Fussgaenger", ETH Zurich; the value Helbing & Molnar's
  social force model draws desired speeds from). Fugger et al. 2000 (TRR 1705) measured 1.36 +- 0.24 m/s at
  crosswalks. A person whose scenario sets a speed (spec.json `people`) keeps it scaled by the same draw
  (speed x draw / 1.34): a slow resident stays slow, but not the same in every seed.
- personal-space preference ~ Normal(1.0, 0.2) m, clipped to [0.5, 1.5]: the comfortable distance to a
  stranger, about 1 m and about circular (Hecht et al. 2019, "The shape of personal space", Acta Psychologica
  193); the spread is ours (that study reports the mean, not a between-person spread we could reuse).
- start delay ~ Exponential(mean 0.8 s), capped at 3 s: the time a pedestrian takes to start walking once it
  may (Fugger et al. 2000: most of 288 pedestrians started within 1 s of the walk signal); the shape is ours.

Applied (APPLIED): the speed (the person's max_vel, HuNavSim's desired speed), the start delay
(HumanSpec.start_delay) and the personal-space preference: the gap the person leaves passing the robot where
there is room (people.avoid.pass_gap_for: 0.5 m for a 1 m preference, in proportion), the only personal
distance of the simulated people's avoidance (their social force between people has none).
"""

from __future__ import annotations

import json
import math
from functools import lru_cache
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict

from socnavgen.bodies import PERSON_TOP_SPEED

SPEED_MEAN, SPEED_SD, SPEED_RANGE = 1.34, 0.26, (0.5, PERSON_TOP_SPEED)
SPACE_MEAN, SPACE_SD, SPACE_RANGE = 1.0, 0.2, (0.5, 1.5)
DELAY_MEAN, DELAY_MAX = 0.8, 3.0
APPLIED = ("speed", "personal_space", "start_delay")  # traits the simulator takes (apply_traits)
STREAM = 0x50_45_4F_50_4C_45  # "PEOPLE": the variation's random stream, apart from the simulator's spawn draws

DISTRIBUTIONS = {
    "speed": f"preferred walking speed ~ Normal({SPEED_MEAN}, {SPEED_SD}) m/s clipped to [{SPEED_RANGE[0]}, "
             f"{SPEED_RANGE[1]}] (Weidmann 1993; a speed the scenario sets is scaled by draw / {SPEED_MEAN})",
    "personal_space": f"personal-space preference ~ Normal({SPACE_MEAN}, {SPACE_SD}) m clipped to "
                      f"[{SPACE_RANGE[0]}, {SPACE_RANGE[1]}] (mean: Hecht et al. 2019)",
    "start_delay": f"start delay ~ Exponential(mean {DELAY_MEAN} s) capped at {DELAY_MAX} s (Fugger et al. 2000)",
    "spawn": "start point uniform within 1.5 m of the person's first node (SocRATES; the simulator draws it)",
}


class Traits(BaseModel):
    """One person's draw for one seed."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    speed: float  # m/s: desired (max) walking speed
    personal_space: float  # m: preferred distance to others (the gap it leaves passing the robot: pass_gap_for)
    start_delay: float  # s: stands this long before walking (HumanSpec.start_delay)


def _clipped_normal(rng: np.random.Generator, mean: float, sd: float, low: float, high: float) -> float:
    return float(np.clip(rng.normal(mean, sd), low, high))


def draw_people(scenario: str, seed: int, names: list[str],
                spec_speeds: dict[str, float] | None = None) -> dict[str, Traits]:
    """Each person's traits for this scenario and seed (deterministic; each person from its own stream, so
    that adding a person to a scenario does not change the others' draws, and scenarios draw independently).
    Drawn once per worker, scenario and seed: every policy of a campaign meets the same people."""
    return dict(_drawn(scenario, int(seed), tuple(names), tuple(sorted((spec_speeds or {}).items()))))


@lru_cache(maxsize=4096)
def _drawn(scenario: str, seed: int, names: tuple[str, ...],
           speeds: tuple[tuple[str, float], ...]) -> dict[str, Traits]:
    """draw_people's draw, kept (Traits are frozen; callers get a copy of the dict)."""
    spec_speeds = dict(speeds)
    out = {}
    for name in names:
        rng = np.random.default_rng([STREAM, int(seed), *f"{scenario}|{name}".encode()])
        draw = _clipped_normal(rng, SPEED_MEAN, SPEED_SD, *SPEED_RANGE)
        speed = draw if name not in spec_speeds else float(np.clip(spec_speeds[name] * draw / SPEED_MEAN, 0.1,
                                                                   PERSON_TOP_SPEED))
        space = _clipped_normal(rng, SPACE_MEAN, SPACE_SD, *SPACE_RANGE)
        delay = min(DELAY_MAX, float(rng.exponential(DELAY_MEAN)))
        out[name] = Traits(speed=round(speed, 4), personal_space=round(space, 4), start_delay=round(delay, 3))
    return out


def people_of(run: Any) -> tuple[list[str], dict[str, float]]:
    """(names of the run's people in agent order, speeds its spec.json sets) of a LoadedRun."""
    plan = run.paths()
    names = [h.name for h in sorted(plan.humans, key=lambda h: h.agent_id)]
    spec = run.spec()
    speeds = {n: p.speed for n, p in (spec.people.items() if spec is not None else []) if p.speed is not None}
    return names, speeds


def apply_traits(sim: Any, traits: dict[str, Traits]) -> None:
    """Give the simulation's people their drawn speeds (what HumanSpec.max_vel sets: the desired speed and the
    pace a paced person starts from), start delays (HumanSpec.start_delay) and passing gaps from their
    personal-space preferences (HumanSpec.pass_gap), before it runs. Until load_simulation takes per-person
    traits (SIM_NEEDS.md), this writes the fields of Simulation.people that those HumanSpec fields initialise."""
    from socnavgen.sim.people.avoid import pass_gap_for

    people = sim.people
    for i, human in enumerate(sim.humans):
        mine = traits.get(human.name)
        if mine is not None:
            people.max_speed[i] = mine.speed
            people.pace[i] = mine.speed
            people.start_delay[i] = mine.start_delay
            people.pass_gap[i] = pass_gap_for(mine.personal_space)


def summary(traits: dict[str, Traits]) -> dict[str, Any]:
    """The row's record of the draw: every person's traits (JSON) and the mean speed."""
    speeds = [t.speed for t in traits.values()]
    return {"people_traits": json.dumps({n: t.model_dump() for n, t in traits.items()}, separators=(",", ":")),
            "mean_person_speed": float(np.mean(speeds)) if speeds else math.nan}
