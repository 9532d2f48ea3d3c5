"""Helpers for the simulator tests: tiny worlds built in code, tree templates, scripted robots."""

from __future__ import annotations

import numpy as np

from socnavgen.sim import (
    HumanSpec,
    RobotAction,
    RobotBody,
    RobotSpeech,
    SimConfig,
    Simulation,
    World,
    empty_room,
)

REGULAR = ('<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
           '<SetBlackboard output_key="timestep" value="{dt}"/>'
           '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence>')

# a holonomic body that does what it is told at once: for tests about people or trees, not the robot's body
INSTANT = RobotBody(kinematics="holonomic", max_speed=2.0, max_accel=100.0, max_decel=100.0)


def tree_xml(body: str, fmt: int = 3) -> str:
    """A main tree around `body`, including the library's RegularNavTree."""
    head = '<root main_tree_to_execute="MainTree" BTCPP_format="4">' if fmt == 4 else \
        '<root main_tree_to_execute="MainTree">'
    return f'{head}\n<include path="BTRegularNav.xml"/>\n<BehaviorTree ID="MainTree">\n{body}\n</BehaviorTree>\n</root>\n'


def give_way_tree(gate: str) -> str:
    """A tree that gives way while `gate` (conditions, in order) holds, else walks its path (RegularNav): the shape
    the model most often writes."""
    return tree_xml(f'<Fallback><Sequence>{gate}<GiveWaytoRobot agent_id="{{id}}" time_step="{{dt}}"/></Sequence>'
                    f'{REGULAR}</Fallback>')


def nav_tree(body: str) -> str:
    """A main tree around `body`, which may use the RegularNavTree SubTree: its two ports are filled first."""
    return tree_xml('<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
                    f'<SetBlackboard output_key="timestep" value="{{dt}}"/>{body}</Sequence>')


class Stay:
    """A robot that never moves."""

    def act(self, obs):  # noqa: ANN001, ANN201
        return RobotAction(0.0, 0.0)


class Drive:
    """A robot driving at a constant velocity (optionally saying something)."""

    def __init__(self, vx: float, vy: float = 0.0, gesture: int | None = None) -> None:
        self.vx, self.vy, self.gesture = vx, vy, gesture

    def act(self, obs):  # noqa: ANN001, ANN201
        return RobotAction(self.vx, self.vy, self.gesture)


def human(name: str = "human1", start=(2.0, 5.0), goals=((18.0, 5.0),), **kw) -> HumanSpec:  # noqa: ANN001
    return HumanSpec(name=name, start=start, goals=list(goals), **kw)


def make_sim(humans: list[HumanSpec], trees: list[str], robot_path, policy=None, world: World | None = None,  # noqa: ANN001
             rules=None, script=None, pacing=None, encounters=None, nodes=None, **config) -> Simulation:  # noqa: ANN001
    speech = RobotSpeech(script=script, rules=list(rules or []), encounter_points=dict(encounters or {}),
                         node_points=dict(nodes or {}))
    return Simulation(world or empty_room(20.0, 10.0), humans, trees, list(robot_path), policy or Stay(),
                      SimConfig(**config), speech=speech, pacing=pacing)


def xy(trace, step: int, agent: int = 0) -> complex:  # noqa: ANN001
    return complex(trace.humans[step, agent, 0], trace.humans[step, agent, 1])


def positions(sim: Simulation) -> np.ndarray:
    """Every person's position now (a copy)."""
    return np.array(sim.people.pos)
