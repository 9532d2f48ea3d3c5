"""Policies take `params:` in campaign files and `sweep:` over them: each combination is a policy of its own,
the params reach the robot (its speed, its body) and are in every row; a wrong key is one message."""

from __future__ import annotations

import json

import pytest

from socnavgen.campaign.runner import check_policies, run_campaign
from socnavgen.campaign.spec import parse_campaign
from socnavgen.campaign.store import read_episodes
from socnavgen.errors import InputFileError
from tests.campaign.conftest import campaign_yaml


def test_a_sweep_expands_into_policies_whose_params_reach_the_robot(tmp_path) -> None:  # noqa: ANN001
    sweep = "{name: slow, robot: scripted, params: {kinematics: holonomic}, sweep: {max_speed: [0.3, 0.6]}}"
    spec = parse_campaign(campaign_yaml(["parallel-traffic"], [sweep], 1, timeout=8.0))
    assert [p.name for p in spec.policies] == ["slow-max_speed-0.3", "slow-max_speed-0.6"]
    assert spec.policies[0].params == {"kinematics": "holonomic", "max_speed": 0.3}
    out = tmp_path / "o"
    run_campaign(spec, out, executor="inline")
    rows = {r["policy"]: r for r in read_episodes(out)[0].to_pylist()}
    slow, fast = rows["slow-max_speed-0.3"], rows["slow-max_speed-0.6"]
    assert json.loads(slow["params"]) == {"kinematics": "holonomic", "max_speed": 0.3}
    assert json.loads(slow["robot_body"])["kinematics"] == "holonomic"
    assert slow["path_length"] < 0.75 * fast["path_length"]  # the same 8 s at half the speed


@pytest.mark.parametrize(("entry", "words"), [
    ("{name: a, robot: scripted, params: {warp: 2.0}}", "has no parameter 'warp'"),
    ("{name: a, robot: scripted, params: {kinematics: hovercraft}}", "kinematics"),
    ("{name: a, robot: scripted, params: {max_speed: 1.5}}", "above its body's"),
    ("{name: a, robot: scripted, params: {max_speed: fast}}", "a number"),
])
def test_a_wrong_param_is_one_message(entry: str, words: str) -> None:
    spec = parse_campaign(campaign_yaml(["parallel-traffic"], [entry], 1))
    with pytest.raises(InputFileError, match=words):
        check_policies(spec)


def test_a_sweep_that_is_not_a_mapping_of_lists_is_refused() -> None:
    with pytest.raises(InputFileError, match="sweep"):
        parse_campaign(campaign_yaml(["parallel-traffic"], ["{name: a, robot: scripted, sweep: {max_speed: 0.3}}"], 1))


def test_blame_falls_on_the_policy_when_the_scenario_verifies_with_the_default_robot(tmp_path) -> None:  # noqa: ANN001
    from tests.campaign.conftest import POLICIES

    spec = parse_campaign(campaign_yaml(["frontal-approach"], ["scripted", f"{{name: rude, robot: '{POLICIES}:StraightThrough'}}"],
                                        1, timeout=60.0))
    out = tmp_path / "o"
    run_campaign(spec, out, executor="inline")
    rows = {r["policy"]: r for r in read_episodes(out)[0].to_pylist()}
    assert rows["scripted"]["verified"]  # the scenario happens with the default robot
    assert not rows["rude"]["verified"]
    failed = [v for v in json.loads(rows["rude"]["verdicts"]) if v["required"] and not v["passed"]]
    assert failed and all(v["blame"] == "policy" and v["blame_human"] is None for v in failed)


def test_the_default_robots_own_episode_answers_whether_the_scenario_verifies_with_it(tmp_path, monkeypatch) -> None:  # noqa: ANN001
    """Blame needs the default robot's verdict on the failing episode's seed: a campaign that ran the default
    robot on that seed in this worker already has it (one simulation fewer), and the rows are the same
    whichever policy runs first (then the verdict is simulated on demand)."""
    import socnavgen.campaign.episode as episode
    from tests.campaign.conftest import POLICIES

    simulated: list[str] = []
    inner = episode.simulate_episode

    def counting(ep, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        simulated.append(ep.robot)
        return inner(ep, *args, **kwargs)

    monkeypatch.setattr(episode, "simulate_episode", counting)
    rude = f"{{name: rude, robot: '{POLICIES}:StraightThrough'}}"
    tables = {}
    for order in (["scripted", rude], [rude, "scripted"]):
        simulated.clear()
        out = tmp_path / str(len(tables))
        run_campaign(parse_campaign(campaign_yaml(["frontal-approach"], order, 1, timeout=60.0)), out, executor="inline")
        tables[order[0]] = (list(simulated), {r["policy"]: r for r in read_episodes(out)[0].to_pylist()})
    default_first, rude_first = tables["scripted"], tables[rude]
    assert default_first[0].count("scripted") == 1  # its own episode; the rude one's blame reused its verdict
    assert rude_first[0].count("scripted") == 2  # asked for by the rude episode's blame, then its own episode
    for policy in ("scripted", "rude"):
        for column in ("verified", "verify_failed", "verdicts", "success", "steps"):
            assert default_first[1][policy][column] == rude_first[1][policy][column], (policy, column)
    assert any(v["blame"] == "policy" for v in json.loads(default_first[1]["rude"]["verdicts"]))
