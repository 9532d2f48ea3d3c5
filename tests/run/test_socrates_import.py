"""A SocRATES user brings their scenarios along: the files SocRATES saves (one combined scenario file, or a
folder of its separate replies) become a run folder on the location they were made for, which then
simulates, verifies and exports like any run; the real saved scenarios parse, and a scenario made for
another map is refused with the mistakes named."""

from __future__ import annotations

import json
from pathlib import Path

import networkx as nx
import pytest

from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.export import export_run
from socnavgen.location import load_location
from socnavgen.run import RunFolder
from socnavgen.run.socrates_import import import_socrates_run, read_socrates
from socnavgen.sim import simulate_run
from socnavgen.verify import verify_trace

WAREHOUSE = Path(__file__).resolve().parents[2] / "examples" / "locations" / "warehouse"
TREE = """<root main_tree_to_execute='HumanTree'>
    <include path='BTRegularNav.xml'/>
    <BehaviorTree ID='HumanTree'>
        <Fallback name='F'>
            <Sequence name='Look'>
                <IsRobotVisible agent_id='{id}' distance='3.0'/>
                <LookAtRobot agent_id='{id}'/>
            </Sequence>
            <Sequence name='Walk'>
                <SetBlackboard output_key='agentid' value='{id}'/>
                <SetBlackboard output_key='timestep' value='{dt}'/>
                <SubTree ID='RegularNavTree' id='agentid' dt='timestep'/>
            </Sequence>
        </Fallback>
    </BehaviorTree>
</root>"""


def _route() -> list[str]:
    graph = load_location(WAREHOUSE).graph
    a, b = max(((a, b) for a in graph for b in graph), key=lambda p: nx.shortest_path_length(graph, *p))
    return nx.shortest_path(graph, a, b)


def combined(route: list[str]) -> dict:
    """The shape of SocRATES's <experiment>_response_traj.json (scenario stored as JSON text)."""
    scenario = {"scenariodescription": "A robot crosses the warehouse; a worker comes the other way.",
                "numberofhumans": 1, "humanbehavior": [{"name": "Human 1", "behavior": "looks at the robot"}],
                "expectedrobotbehavior": "pass the worker politely"}
    return {"scenario": json.dumps(scenario), "groupids": {"human1": -1},
            "trajectories": {"robot": route, "human1": route[::-1]},
            "interaction_points": {"human1": route[len(route) // 2]}, "behavior_trees": {"human1": TREE}}


def test_a_combined_scenario_file_becomes_a_run_that_simulates_verifies_and_exports(tmp_path: Path) -> None:
    route = _route()
    source = tmp_path / "crossing_response_traj.json"
    source.write_text(json.dumps(combined(route)))
    folder, notes = import_socrates_run(source, WAREHOUSE, tmp_path / "run")
    assert notes == []
    paths = folder.read_paths()
    assert paths.robot == route and paths.human("human1").path == route[::-1]
    assert paths.human("human1").interaction_point == route[len(route) // 2]
    assert folder.read_behavior("human1").startswith("<root main_tree_to_execute='HumanTree'>")
    scenario = folder.read_scenario()
    assert scenario.human_behaviors == {"human1": "looks at the robot"}
    assert scenario.expected_robot_behavior == "pass the worker politely"
    assert folder.read_manifest().status == "done" and folder.location().name == "warehouse"
    trace = simulate_run(folder.root, timeout=30.0, save=False)
    assert trace.human_names == ["human1"] and trace.steps > 10
    report = verify_trace(folder.root, trace)
    assert report.findings and not report.spec  # judged on the criteria derived from paths and trees
    result = export_run(folder.root, "socrates", tmp_path / "export")
    assert "hunav_agent_manager/behavior_trees/LLMBT_0.xml" in result.files


def test_a_folder_of_separate_replies_is_read_like_socrates_wrote_it(tmp_path: Path) -> None:
    route = _route()
    replies = tmp_path / "responses"
    replies.mkdir()
    (replies / "reponse_sc.json").write_text(json.dumps({
        "scenariodescription": "two workers", "numberofhumans": 2,
        "humanbehavior": {"Human 1": {"Human Task": "stocking", "Behavior Towards Robot": "looks"},
                          "Human 2": "walks"}}))
    (replies / "reponse_traj.json").write_text(json.dumps({
        "reasoning": "both meet the robot", "trajectories": {"ROBOT": route, "HUMAN 1": route[::-1],
                                                              "HUMAN_2": route[-2:]},
        "groupids": {"HUMAN 1": -1, "HUMAN 2": -1}}))
    (replies / "reponse_bt_1.json").write_text(json.dumps({"reasoning": "r", "tree": TREE}))
    (replies / "LLMBT_1.xml").write_text(TREE)  # human2, as the simulator files number them (from 0)
    (replies / "custom_agents.yaml").write_text("ignored: true\n")
    folder, _ = import_socrates_run(replies, WAREHOUSE, tmp_path / "run")
    paths = folder.read_paths()
    assert [h.name for h in paths.humans] == ["human1", "human2"] and paths.reasoning == "both meet the robot"
    assert folder.read_scenario().human_behaviors["human1"] == "Human Task: stocking Behavior Towards Robot: looks"
    assert sorted(folder.behaviors()) == ["human1", "human2"]


def test_what_does_not_fit_is_refused_with_every_mistake_named(tmp_path: Path) -> None:
    route = _route()
    data = combined(route)
    data["trajectories"]["human1"] = ["zz", *route[::-1]]
    (tmp_path / "a.json").write_text(json.dumps(data))
    with pytest.raises(ValidationFailed, match="do not fit this location's scene graph.*zz") as info:
        import_socrates_run(tmp_path / "a.json", WAREHOUSE, tmp_path / "run")
    assert "another location" in info.value.hint and not (tmp_path / "run").exists()
    data = combined(route)
    data["behavior_trees"]["human1"] = TREE.replace("LookAtRobot", "Dance")
    (tmp_path / "b.json").write_text(json.dumps(data))
    with pytest.raises(ValidationFailed, match="Dance"):
        import_socrates_run(tmp_path / "b.json", WAREHOUSE, tmp_path / "run")
    data = combined(route)
    data["trajectories"]["Visitor"] = route
    (tmp_path / "c.json").write_text(json.dumps(data))
    with pytest.raises(InputFileError, match="'Visitor' is neither the robot nor a human"):
        import_socrates_run(tmp_path / "c.json", WAREHOUSE, tmp_path / "run")
    data = combined(route)
    del data["behavior_trees"]
    (tmp_path / "d.json").write_text(json.dumps(data))
    with pytest.raises(ValidationFailed, match="no behavior tree for human1"):
        import_socrates_run(tmp_path / "d.json", WAREHOUSE, tmp_path / "run")
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "mine.txt").write_text("x")
    (tmp_path / "e.json").write_text(json.dumps(combined(route)))
    with pytest.raises(InputFileError, match="not empty"):
        import_socrates_run(tmp_path / "e.json", WAREHOUSE, tmp_path / "run")


def test_an_interaction_point_off_the_robots_path_is_dropped_with_a_note(tmp_path: Path) -> None:
    route = _route()
    data = combined(route)
    data["trajectories"]["human1"] = route[-1:]
    data["interaction_points"]["human1"] = route[0]
    (tmp_path / "s.json").write_text(json.dumps(data))
    folder, notes = import_socrates_run(tmp_path / "s.json", WAREHOUSE, tmp_path / "run")
    assert folder.read_paths().human("human1").interaction_point is None and "dropped" in notes[0]


@pytest.mark.parametrize("name", ["follow_corner.json", "first_exp_response_traj.json"])
def test_the_real_saved_scenarios_parse(name: str, reference_dir: Path, tmp_path: Path) -> None:
    """SocRATES's own saved scenarios (scenario as JSON text or as an object, interaction points or none)."""
    source = reference_dir / "data" / "socrates-generator" / "scenarios" / name
    sc = read_socrates(source)
    assert "robot" in sc.trajectories and set(sc.trees) == {"human1", "human2"}
    assert sc.description and set(sc.behaviors) == {"human1", "human2"}
    # they were made for SocRATES's own warehouse annotation, not ours: refused with the unknown nodes named
    with pytest.raises(ValidationFailed, match="is not in the scene graph"):
        import_socrates_run(source, WAREHOUSE, tmp_path / "run")
    assert not (tmp_path / "run").exists() and not RunFolder(tmp_path / "run").paths_path.exists()


def test_the_command(tmp_path: Path) -> None:
    from tests.export.test_cli import run_cli

    (tmp_path / "s.json").write_text(json.dumps(combined(_route())))
    done = run_cli("run", "import-socrates", str(tmp_path / "s.json"), "--location", str(WAREHOUSE),
                   "-o", str(tmp_path / "run"))
    assert done.returncode == 0 and "imported" in done.stdout and "socnavgen simulate" in done.stdout
    again = run_cli("run", "import-socrates", str(tmp_path / "s.json"), "--location", str(WAREHOUSE),
                    "-o", str(tmp_path / "run"))
    assert again.returncode == 2 and "not empty" in again.stderr and "Traceback" not in again.stderr
