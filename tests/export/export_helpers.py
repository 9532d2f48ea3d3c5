"""Builders for export tests (and anyone who needs a run folder): a tiny location whose map origin
is NOT centred (so a wrong y formula shows), run folders on any location, and trees."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from socnavgen.run import HumanPlan, PathPlan, RunFolder, ScenarioProposal, ScenarioRequest
from tests.synthetic import write_location

# 60 x 40 px, 0.05 m/px, origin (-3.0, 1.5): pixel centre (px, py) -> (-3 + 0.05 (px + 0.5), 1.5 + 0.05 (40 - py - 0.5))
WIDTH, HEIGHT, RES, ORIGIN = 60, 40, 0.05, (-3.0, 1.5)
NODES = {"aa": (10, 20), "ee": (30, 20), "bb": (50, 20), "cc": (50, 5), "dd": (10, 5)}
EDGES = [("aa", "ee"), ("ee", "bb"), ("bb", "cc"), ("cc", "dd"), ("dd", "aa")]

REGULAR_TREE = """<root main_tree_to_execute="WalkTree">
    <include path="BTRegularNav.xml"/>
    <BehaviorTree ID="WalkTree">
        <Sequence name="Walk">
            <SetBlackboard output_key="agentid" value="{id}"/>
            <SetBlackboard output_key="timestep" value="{dt}"/>
            <SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>
        </Sequence>
    </BehaviorTree>
</root>
"""

GIVE_WAY_TREE = """<root main_tree_to_execute="GiveWayTree">
    <include path="BTRegularNav.xml"/>
    <BehaviorTree ID="GiveWayTree">
        <Fallback name="ExcuseMe">
            <Sequence name="GiveWay">
                <RobotSays agent_id="{id}" message="4"/>
                <GiveWaytoRobot agent_id="{id}" time_step="{dt}"/>
            </Sequence>
            <Sequence name="RegNav">
                <SetBlackboard output_key="agentid" value="{id}"/>
                <SetBlackboard output_key="timestep" value="{dt}"/>
                <SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>
            </Sequence>
        </Fallback>
    </BehaviorTree>
</root>
"""

# Only nodes that HuNavSim 2.x has: stop and say WAIT when the robot is near, else walk.
TRANSLATABLE_TREE = """<root main_tree_to_execute="WaitTree">
    <include path="BTRegularNav.xml"/>
    <BehaviorTree ID="WaitTree">
        <Fallback name="WaitOrWalk">
            <Sequence name="Wait">
                <IsRobotNearby agent_id="{id}" distance="2.0"/>
                <MakeGesture agent_id="{id}" message="1"/>
                <LookAtRobot agent_id="{id}"/>
            </Sequence>
            <Sequence name="Follow">
                <IsRobotVisible agent_id="{id}" distance="5.0"/>
                <FollowRobot agent_id="{id}" time_step="{dt}"/>
            </Sequence>
            <Sequence name="RegNav">
                <SetBlackboard output_key="agentid" value="{id}"/>
                <SetBlackboard output_key="timestep" value="{dt}"/>
                <SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>
            </Sequence>
        </Fallback>
    </BehaviorTree>
</root>
"""

CURIOUS_TREE = """<root main_tree_to_execute="CuriousTree">
    <include path="BTRegularNav.xml"/>
    <BehaviorTree ID="CuriousTree">
        <Fallback name="Curious">
            <Sequence name="Look">
                <IsRobotVisible agent_id="{id}" distance="10"/>
                <Inverter>
                    <TimeExpiredCondition seconds="30" ts="{dt}" only_once="true"/>
                </Inverter>
                <FollowRobot agent_id="{id}" time_step="{dt}"/>
            </Sequence>
            <Sequence name="RegNav">
                <SetBlackboard output_key="agentid" value="{id}"/>
                <SetBlackboard output_key="timestep" value="{dt}"/>
                <SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>
            </Sequence>
        </Fallback>
    </BehaviorTree>
</root>
"""


def expected_world(node: str) -> tuple[float, float]:
    """Hand formula of the map_server convention (pixel centres, origin = lower-left corner)."""
    px, py = NODES[node]
    return ORIGIN[0] + RES * (px + 0.5), ORIGIN[1] + RES * (HEIGHT - py - 0.5)


def build_location(root: Path) -> Path:
    free = np.ones((HEIGHT, WIDTH), dtype=bool)
    free[0, :] = free[-1, :] = free[:, 0] = free[:, -1] = False
    return write_location(root, free, NODES, EDGES, resolution=RES, origin=ORIGIN, name="tiny_offset",
                          description="a small rectangular room", default_type="CORNER",
                          schema_nodes=["CORNER", "PASSAGE"])


def build_run(root: Path, location: Path, plan: PathPlan, trees: dict[str, str]) -> Path:
    """An ordinary run folder, as `generate` would leave it."""
    run = RunFolder(root)
    root.mkdir(parents=True, exist_ok=True)
    run.write_request(ScenarioRequest(location=str(location), context="test", task="cross the room"))
    run.write_scenario(ScenarioProposal(
        scenario_description="test", number_of_humans=len(plan.humans),
        human_behaviors={h.name: "walks" for h in plan.humans}, expected_robot_behavior="passes"))
    run.write_paths(plan)
    for name, xml in trees.items():
        run.write_behavior(name, xml)
    return root


def default_plan() -> PathPlan:
    return PathPlan(robot=["aa", "ee", "bb", "cc"], humans=[
        HumanPlan(name="human1", path=["cc", "bb", "ee"], interaction_point="ee"),
        HumanPlan(name="human2", path=["dd"], group_id=-1)])




def shape(value: object) -> object:
    """Keys, types and nesting of a YAML/JSON value, without the values."""
    if isinstance(value, dict):
        return {k: shape(v) for k, v in value.items()}
    if isinstance(value, list):
        return [shape(value[0])] if value else []
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, (int, float)):
        return "number"
    return type(value).__name__


def agent_shape(params: dict, name: str) -> dict:
    """An agent block with goal names replaced by their position in `goals` (g0 vs g1 naming)."""
    agent = dict(params[name])
    goals = agent.pop("goals")
    out = shape(agent)
    for k, g in enumerate(goals):
        out.pop(g)
        out[f"goal{k}"] = shape(params[name][g])
    return out
