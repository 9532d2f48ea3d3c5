"""What decides an episode, as digests (run/digest.py): the scenario's files (its run folder and location),
the policy's source and parameters, the simulation settings and socnavgen's version. Every row stores the
digest of its episode's inputs; a re-run keeps a row only for the very same inputs, runs the others again,
and says what changed (OUT/inputs.json keeps the parts, to compare with)."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from socnavgen.campaign.episode import Episode, EpisodeSettings, episode_key
from socnavgen.campaign.scenarios import Suite
from socnavgen.campaign.spec import CampaignSpec
from socnavgen.run.digest import combine, location_digest, policy_digest, run_files_digest, version
from socnavgen.safeio import atomic_write_json, load_json_file

INPUTS_FILE = "inputs.json"


SHORT = 12  # hex digits kept of each part's digest


@dataclass
class Inputs:
    version: str
    settings: str
    scenarios: dict[str, str] = field(default_factory=dict)  # scenario id -> digest of its files
    policies: dict[str, str] = field(default_factory=dict)  # policy name -> digest of its source and parameters

    def digest(self, scenario: str, policy: str) -> str:
        """What a row stores: the digests of its four inputs, so a changed row can say which one changed."""
        return "/".join((self.version, self.settings[:SHORT], self.scenarios[scenario][:SHORT],
                         self.policies[policy][:SHORT]))

    def of(self, ep: Episode) -> str:
        return self.digest(ep.scenario.id, ep.policy)

    def plan(self, scenarios: list[str], policies: list[str], seeds: list[int]) -> dict[str, str]:
        """episode key -> inputs digest for every episode of the campaign."""
        return {episode_key(s, p, k): self.digest(s, p) for s in scenarios for p in policies for k in seeds}


def what_changed(old: str | None, new: str, scenario: str, policy: str) -> str:
    """Why a stored row's inputs differ from the episode's now, in words."""
    before, now = (old or "").split("/"), new.split("/")
    if len(before) != len(now):
        return "its row records no inputs (an older socnavgen wrote it)"
    names = ("socnavgen's version", "the simulation settings", f"scenario {scenario}'s files",
             f"policy {policy}'s source or parameters")
    return ", ".join(n for n, a, b in zip(names, before, now, strict=True) if a != b) + " changed"


def inputs_of(spec: CampaignSpec, suite: Suite, settings: EpisodeSettings) -> Inputs:
    from socnavgen.location import load_location

    locations: dict[str, str] = {}
    scenarios = {}
    for s in suite.scenarios:
        if s.location_dir not in locations:
            locations[s.location_dir] = location_digest(load_location(Path(s.location_dir)))
        scenarios[s.id] = combine(run_files_digest(s.run_dir), locations[s.location_dir])
    from socnavgen.sim.robot.api import BASELINES

    policies = {p.name: combine(_robot_name(p.robot), policy_digest(BASELINES.get(p.robot, p.robot)),
                                p.model_dump(mode="json", exclude={"name", "robot"}))
                for p in spec.policies}
    return Inputs(version=version(), settings=combine(asdict(settings)), scenarios=scenarios, policies=policies)


def _robot_name(robot: str) -> str:
    """A built-in name, or the class of `path:Class` (not the path: a moved campaign folder is the same)."""
    return robot.rpartition(":")[2]


def read_inputs(out: Path) -> Inputs | None:
    path = Path(out) / INPUTS_FILE
    if not path.is_file():
        return None
    try:
        data: Any = load_json_file(path)
        return Inputs(**data)
    except Exception:  # noqa: BLE001 - an unreadable record only means we cannot say what changed
        return None


def write_inputs(out: Path, inputs: Inputs) -> None:
    atomic_write_json(Path(out) / INPUTS_FILE, json.loads(json.dumps(asdict(inputs))))
