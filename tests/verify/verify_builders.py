"""Builders for verify tests: a tiny real location (12 m x 6 m corridor), a run folder, and traces.

Map: 240 x 120 px at 0.05 m/px, nav2 origin (0, 0): pixel (px, py) -> (0.05 (px + 0.5), 0.05 (119.5 - py)).
Nodes: a1 (20, 60) -> (1.025, 2.975); b2 (120, 60) -> (6.025, 2.975); c3 (220, 60) -> (11.025, 2.975);
d4 (120, 15) -> (6.025, 5.225).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer

from socnavgen.cli.verify_cmd import register_verify
from socnavgen.run.folder import RunFolder
from socnavgen.run.models import HumanPlan, PathPlan, ScenarioRequest
from socnavgen.sim.trace import Trace
from tests.synthetic import walled_room, write_location

NODE_WORLD = {"a1": (1.025, 2.975), "b2": (6.025, 2.975), "c3": (11.025, 2.975), "d4": (6.025, 5.225)}

GIVE_WAY_XML = """<root main_tree_to_execute="GiveWayTree">
  <include path="BTRegularNav.xml"/>
  <BehaviorTree ID="GiveWayTree">
    <Fallback>
      <Sequence name="give way on EXCUSE ME">
        <IsRobotVisible agent_id="{id}" distance="4.0"/>
        <RobotSays agent_id="{id}" message="4"/>
        <GiveWaytoRobot agent_id="{id}" time_step="{dt}"/>
      </Sequence>
      <Sequence>
        <Inverter><IsRobotNearby agent_id="{id}" distance="1.0"/></Inverter>
        <MakeGesture agent_id="{id}" message="0"/>
        <SetBlackboard output_key="agentid" value="{id}"/>
        <SetBlackboard output_key="timestep" value="{dt}"/>
        <SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>
      </Sequence>
    </Fallback>
  </BehaviorTree>
</root>
"""

REGULAR_XML = """<root main_tree_to_execute="Walk">
  <include path="BTRegularNav.xml"/>
  <BehaviorTree ID="Walk">
    <Sequence>
      <SetBlackboard output_key="agentid" value="{id}"/>
      <SetBlackboard output_key="timestep" value="{dt}"/>
      <SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def make_location(root: Path) -> Path:
    free = walled_room(120, 240, wall=4)
    free[70:116, 100:140] = False  # a block below the crossing
    return write_location(root, free, {"a1": (20, 60), "b2": (120, 60), "c3": (220, 60), "d4": (120, 15)},
                          [("a1", "b2"), ("b2", "c3"), ("b2", "d4")], name="corridor",
                          description="a straight corridor", node_types={"a1": "ROOM", "b2": "CORRIDOR",
                                                                         "c3": "ROOM", "d4": "ROOM"},
                          schema_nodes=["ROOM", "CORRIDOR"], default_edge="PASSAGEWAY", image="map.png")


def write_run(root: Path, location: Path, plan: PathPlan, trees: dict[str, str], card: str | None = None) -> Path:
    run = RunFolder(root)
    root.mkdir(parents=True, exist_ok=True)
    run.write_request(ScenarioRequest(location=str(location), context="test", task="cross", card=card))
    run.write_paths(plan)
    for name, xml in trees.items():
        run.write_behavior(name, xml)
    return root


def make_give_way_run(root: Path, location: Path) -> Path:
    """Robot a1 -> b2 -> c3; human1 c3 -> b2 -> a1, interaction point b2, gives way on EXCUSE ME."""
    plan = PathPlan(robot=["a1", "b2", "c3"],
                    humans=[HumanPlan(name="human1", path=["c3", "b2", "a1"], interaction_point="b2")])
    return write_run(root, location, plan, {"human1": GIVE_WAY_XML})


NODE_NAMES = ["RegularNav", "GiveWaytoRobot", "IsRobotVisible", "RobotSays", "MakeGesture", "IsRobotNearby"]


def build_trace(t, robot_xy, humans_xy, *, dt=0.5, node_names=NODE_NAMES, actions=None, fired=None,
                robot_gesture=None, human_gesture=None, groups=None, goal=None, end_reason="") -> Trace:
    """Trace from positions; velocities by finite difference, yaw from the velocity direction.
    `actions`: {(step, human): name}; `fired`: {(step, human): [names]}."""
    t = np.asarray(t, dtype=float)
    n = len(t)
    robot_xy = np.asarray(robot_xy, dtype=float)
    humans_xy = np.asarray(humans_xy, dtype=float).reshape(n, -1, 2)
    h = humans_xy.shape[1]

    def states(xy: np.ndarray) -> np.ndarray:
        v = np.gradient(xy, t, axis=0) if n > 1 else np.zeros_like(xy)
        yaw = np.arctan2(v[..., 1], v[..., 0])
        return np.concatenate([xy, yaw[..., None], v, np.zeros(xy.shape[:-1] + (1,))], axis=-1)

    action = np.full((n, h), -1, dtype=np.int16)
    for (k, i), name in (actions or {}).items():
        action[k, i] = node_names.index(name)
    succeeded = np.zeros((n, h), dtype=np.int64)
    for (k, i), names in (fired or {}).items():
        for name in names:
            succeeded[k, i] |= np.int64(1) << np.int64(node_names.index(name))
    return Trace(dt=dt, t=t, robot=states(robot_xy), humans=states(humans_xy) if h else np.zeros((n, 0, 6)),
                 human_names=[f"human{i + 1}" for i in range(h)], group_ids=groups or [-1] * h,
                 human_radii=np.full(h, 0.4), robot_radius=0.35, node_names=list(node_names), action=action,
                 succeeded=succeeded,
                 human_gesture=np.asarray(human_gesture, dtype=np.int8) if human_gesture is not None
                 else np.zeros((n, h), np.int8),
                 robot_gesture=np.asarray(robot_gesture, dtype=np.int8) if robot_gesture is not None
                 else np.zeros(n, np.int8),
                 behavior_state=np.zeros((n, h), np.int8), robot_goal=goal, end_reason=end_reason)


def crossing_trace(*, robot_stops_at: float | None = None, say_excuse_me: bool = True) -> Trace:
    """Robot drives +x from a1 at 1 m/s, human1 walks -x from c3 at 1 m/s. With EXCUSE ME it comes head-on along
    the robot's line and, while the robot says it (t 3.5..5), steps 1 m aside (y + 1 by t = 4.5: out of the robot's
    way, what the verifier calls giving way); without it, it walks 1 m to the side (y + 1) the whole way.
    dt 0.5, 21 steps (0..10 s). They pass at t = 5 s at x = 6.025 (node b2), 1.0 m apart.
    The human's tree: IsRobotVisible(4) fires while within 4 m, RobotSays(4) while the robot says 4 (t 3.5..5),
    GiveWaytoRobot executes on those steps, RegularNav otherwise."""
    t = np.arange(21) * 0.5
    rx = 1.025 + t
    if robot_stops_at is not None:
        rx = np.minimum(rx, robot_stops_at)
    hx = 11.025 - t
    hy = 2.975 + np.clip(t - 3.5, 0.0, 1.0) if say_excuse_me else np.full_like(t, 3.975)
    robot = np.stack([rx, np.full_like(t, 2.975)], axis=1)
    human = np.stack([hx, hy], axis=1)[:, None, :]
    dist = np.hypot(rx - hx, 2.975 - hy)
    says = (t >= 3.5) & (t <= 5.0) & say_excuse_me
    actions, fired = {}, {}
    for k in range(21):
        visible = dist[k] <= 4.0
        names = ["IsRobotVisible"] if visible else []
        if visible and says[k]:
            names += ["RobotSays", "GiveWaytoRobot"]
            actions[(k, 0)] = "GiveWaytoRobot"
        else:
            actions[(k, 0)] = "RegularNav"
        fired[(k, 0)] = names
    return build_trace(t, robot, human, actions=actions, fired=fired, robot_gesture=np.where(says, 4, 0),
                       goal=(11.025, 2.975), end_reason="goal" if robot_stops_at is None else "timeout")


def cli_app() -> typer.Typer:
    """A typer app with only `verify` registered (the lead wires it into the main app)."""
    app = typer.Typer()
    register_verify(app)

    @app.command("noop")
    def noop() -> None:  # a second command keeps typer from collapsing the app into `verify` itself
        """Nothing."""

    return app
