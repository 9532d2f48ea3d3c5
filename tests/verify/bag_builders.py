"""Hand-built ROS 2 bags for the bag tests: the states HuNavSim's evaluator records, written with rosbags
directly (not by socnavgen's writer), so the reader is tested on bags it did not produce."""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass, field
from pathlib import Path

from rosbags.rosbag2 import StoragePlugin, Writer

from socnavgen.bag.types import AGENT, AGENTS, header, pose, twist, typestore

from .corpus import NODES_PX, world

NORTH, DOCK = world(*NODES_PX["north"]), world(*NODES_PX["dock"])


@dataclass
class HandAgent:
    ident: int
    name: str
    x: float
    y: float
    group: int = -1
    vx: float = 0.0
    gesture: int = 0


@dataclass
class HandStep:
    t: float  # seconds: header stamp and recording time
    humans: list[HandAgent]
    robot: tuple[float, float] = DOCK
    log: float | None = None  # recording time when it differs from the stamp


@dataclass
class HandBag:
    steps: list[HandStep]
    flavour: str = "socrates"
    humans_topic: str | None = "/human_states"
    robot_topic: str = "/robot_states"
    storage: str = "mcap"
    extra_topics: list[str] = field(default_factory=list)  # std_msgs/String topics with one message each


def corpus_agents(t: float, *, ids: tuple[int, int, int] = (0, 1, 2), names: tuple[str, str, str] | None = None,
                  groups: tuple[int, int, int] = (-1, 0, 0)) -> list[HandAgent]:
    """human1 walking south from `north`, human2 / human3 waiting at `dock` (the corpus run's plan)."""
    names = names or ("human1", "human2", "human3")
    return [HandAgent(ids[0], names[0], NORTH[0], NORTH[1] - 0.5 * t, groups[0], 0.0),
            HandAgent(ids[1], names[1], DOCK[0] - 1.2, DOCK[1], groups[1]),
            HandAgent(ids[2], names[2], DOCK[0] - 1.2, DOCK[1] - 0.8, groups[2])]


def steps(duration: float = 4.0, dt: float = 0.1, **agents: object) -> list[HandStep]:
    return [HandStep(t=k * dt, humans=corpus_agents(k * dt, **agents), robot=(DOCK[0] + 0.5 * k * dt, DOCK[1]))
            for k in range(int(round(duration / dt)) + 1)]


def _agent(store, flavour: str, a: HandAgent, kind: int = 1):  # noqa: ANN001, ANN202
    fields = dict(id=a.ident, type=kind, skin=0, behavior=1, name=a.name, behavior_state=0, group_id=a.group,
                  position=pose(store, a.x, a.y, 0.0), yaw=0.0, velocity=twist(store, a.vx, 0.0, 0.0),
                  desired_velocity=1.5, radius=0.4, linear_vel=abs(a.vx), angular_vel=0.0, goals=[],
                  cyclic_goals=False, goal_radius=0.5, closest_obs=[])
    if flavour == "socrates":
        fields.update(pause_nav=False, gesture=a.gesture)
    return store.types[AGENT](**fields)


def write_hand_bag(path: Path, bag: HandBag) -> Path:
    """A rosbag2 folder at `path` (MCAP or sqlite3); for sqlite3 the embedded message definitions are removed,
    as in bags recorded by ROS 2 Humble."""
    store = typestore(bag.flavour)  # type: ignore[arg-type]
    plugin = StoragePlugin.MCAP if bag.storage == "mcap" else StoragePlugin.SQLITE3
    with Writer(path, version=8, storage_plugin=plugin) as writer:
        humans = writer.add_connection(bag.humans_topic, AGENTS, typestore=store) if bag.humans_topic else None
        robot = writer.add_connection(bag.robot_topic, AGENT, typestore=store)
        for topic in bag.extra_topics:
            conn = writer.add_connection(topic, "std_msgs/msg/String", typestore=store)
            writer.write(conn, 0, store.serialize_cdr(store.types["std_msgs/msg/String"](data="x"), conn.msgtype))
        for step in bag.steps:
            ns = int(round(step.t * 1e9))
            log = int(round((step.log if step.log is not None else step.t) * 1e9))
            rob = _agent(store, bag.flavour, HandAgent(1000, "robot", *step.robot), kind=2)
            writer.write(robot, log, store.serialize_cdr(rob, AGENT))
            msg = store.types[AGENTS](header=header(store, ns),
                                      agents=[_agent(store, bag.flavour, a) for a in step.humans])
            if humans is not None:
                writer.write(humans, log, store.serialize_cdr(msg, AGENTS))
    if bag.storage != "mcap":
        db = next(path.glob("*.db3"))
        with sqlite3.connect(db) as con:
            con.execute("DELETE FROM message_definitions")
    return path
