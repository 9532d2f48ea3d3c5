"""A simulated episode as a ROS 2 bag (MCAP storage) that Foxglove and RViz open: the robot's odometry and
tf, every agent as HuNavSim publishes it (hunav_msgs on /human_states and /robot_states, the topics
HuNavSim's evaluator records), the robot's gesture as the SocRATES wrapper receives it (/robot_gesture),
the map, the scene graph and the planned paths, the agents as markers, and what only socnavgen knows (the
trace's settings and each step's behavior-tree activity, as JSON strings under /socnavgen/) so that the
bag reads back into the very same trace (`socnavgen.bag.reader`)."""

from __future__ import annotations

import json
import math
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime
from rosbags.rosbag2 import StoragePlugin, Writer

from socnavgen.bag import markers
from socnavgen.bag.types import AGENT, AGENTS, Flavour, header, pose, twist, typestore
from socnavgen.bodies import PERSON_GOAL_RADIUS, PERSON_MAX_SPEED, ROBOT_GOAL_TOLERANCE
from socnavgen.errors import InputFileError
from socnavgen.sim.trace import OMEGA, VX, VY, YAW, Trace, X, Y

if TYPE_CHECKING:
    from socnavgen.location import Location
    from socnavgen.run import PathPlan

FORMAT_VERSION = 1  # of the /socnavgen/meta JSON
ROBOT_AGENT_ID = 1000  # HuNavSim's robot agent carries the simulator's model id; any id no human has
PERSON, ROBOT = 1, 2  # hunav_msgs/Agent type constants
FIRST_LLM_BEHAVIOR = 7  # the SocRATES fork's behavior code of LLMBT_<id>.xml
BEH_REGULAR = 1


@dataclass
class Topics:
    """Topic names, HuNavSim's by default (its evaluator subscribes to human_states, robot_states, goal_pose;
    the SocRATES wrapper reads the robot's gesture from /robot_gesture)."""

    humans: str = "/human_states"
    robot: str = "/robot_states"
    goal: str = "/goal_pose"
    robot_gesture: str = "/robot_gesture"
    odom: str = "/odom"
    tf: str = "/tf"
    map: str = "/map"
    scene_graph: str = "/scene_graph"
    paths: str = "/planned_paths"
    agent_markers: str = "/agent_markers"
    meta: str = "/socnavgen/meta"
    bt: str = "/socnavgen/bt"


@dataclass
class BagWriteOptions:
    flavour: Flavour = "socrates"  # hunav_msgs of the SocRATES fork (with gestures) or of upstream HuNavSim
    first_agent_id: int | None = None  # id of human1: None = as the export of that flavour (socrates 0, hunav 1)
    markers_every: int = 1  # agent markers on every n-th step (1 = every step)
    topics: Topics = field(default_factory=Topics)


LATCHED = Qos(QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE, QosDurability.TRANSIENT_LOCAL, QosTime(0, 0),
              QosTime(0, 0), QosLiveliness.AUTOMATIC, QosTime(0, 0), False)


def first_agent_id(options: BagWriteOptions) -> int:
    if options.first_agent_id is not None:
        return options.first_agent_id
    return 0 if options.flavour == "socrates" else 1


def _agent(store: Any, flavour: Flavour, *, ident: int, kind: int, name: str, behavior: int, group: int,
           state: np.ndarray, radius: float, bstate: int, gesture: int, goals: list, goal_radius: float,
           skin: int = 0, desired: float = PERSON_MAX_SPEED) -> Any:
    speed = math.hypot(float(state[VX]), float(state[VY]))
    fields = dict(id=ident, type=kind, skin=skin, behavior=behavior, name=name, behavior_state=bstate,
                  group_id=group, position=pose(store, state[X], state[Y], float(state[YAW])), yaw=float(state[YAW]),
                  velocity=twist(store, state[VX], state[VY], state[OMEGA]), desired_velocity=desired,
                  radius=float(radius), linear_vel=speed, angular_vel=float(state[OMEGA]), goals=goals,
                  cyclic_goals=False, goal_radius=goal_radius, closest_obs=[])
    if flavour == "socrates":
        fields.update(pause_nav=False, gesture=int(gesture))
    return store.types[AGENT](**fields)


def meta_json(trace: Trace, options: BagWriteOptions) -> str:
    """What the hunav messages cannot carry, for an exact read-back."""
    return json.dumps({
        "format": FORMAT_VERSION, "dt": trace.dt, "human_names": trace.human_names, "group_ids": trace.group_ids,
        "human_radii": [float(r) for r in trace.human_radii], "robot_radius": float(trace.robot_radius),
        "node_names": trace.node_names, "robot_goal": list(trace.robot_goal) if trace.robot_goal else None,
        "robot_waypoints": [list(w) for w in trace.robot_waypoints], "end_reason": trace.end_reason,
        "first_agent_id": first_agent_id(options), "flavour": options.flavour, "meta": trace.meta,
    }, default=lambda o: o.item() if isinstance(o, np.generic) else str(o))


def write_bag(trace: Trace, out: Path | str, *, location: Location | None = None, plan: PathPlan | None = None,
              options: BagWriteOptions | None = None) -> Path:
    """Write `trace` as a rosbag2 folder `out` (metadata.yaml + `<name>.mcap`), atomically: it is built
    beside `out` and renamed into place, so an interrupted write leaves no half bag. Returns the .mcap path.
    An existing `out` is refused (a bag is never overwritten)."""
    options = options or BagWriteOptions()
    out = Path(out)
    if out.exists() or out.is_symlink():
        raise InputFileError("the bag folder already exists", file=out, hint="remove it or choose another --bag name")
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        bag = staging / out.name
        _write(trace, bag, location, plan, options)
        (bag / f"{out.name}.mcap").chmod(0o644)
        bag.replace(out)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return out / f"{out.name}.mcap"


def _write(trace: Trace, bag: Path, location: Location | None, plan: PathPlan | None,
           options: BagWriteOptions) -> None:
    store = typestore(options.flavour)
    topics = options.topics
    first = first_agent_id(options)
    ns = [int(round(float(t) * 1e9)) for t in trace.t]
    t0 = ns[0] if ns else 0
    with Writer(bag, version=8, storage_plugin=StoragePlugin.MCAP) as writer:
        def connect(topic: str, msgtype: str, latched: bool = False) -> Any:
            return writer.add_connection(topic, msgtype, typestore=store,
                                         offered_qos_profiles=[LATCHED] if latched else [])

        def put(conn: Any, stamp_ns: int, msg: Any) -> None:
            writer.write(conn, stamp_ns, store.serialize_cdr(msg, conn.msgtype))

        string = store.types["std_msgs/msg/String"]
        put(connect(topics.meta, "std_msgs/msg/String", latched=True), t0, string(data=meta_json(trace, options)))
        goal = trace.robot_goal or (trace.robot_waypoints[-1] if trace.robot_waypoints else None)
        goal_pose = pose(store, goal[0], goal[1], 0.0) if goal else None
        if goal_pose is not None:
            put(connect(topics.goal, "geometry_msgs/msg/PoseStamped"), t0,
                store.types["geometry_msgs/msg/PoseStamped"](header=header(store, t0), pose=goal_pose))
        if location is not None:
            put(connect(topics.map, "nav_msgs/msg/OccupancyGrid", latched=True), t0,
                markers.occupancy_grid(store, location, t0))
            put(connect(topics.scene_graph, markers.MARKER_ARRAY, latched=True), t0,
                markers.scene_graph_markers(store, location, t0))
        put(connect(topics.paths, markers.MARKER_ARRAY, latched=True), t0,
            markers.path_markers(store, location, plan, trace, t0))
        conns = {name: connect(topic, kind) for name, topic, kind in (
            ("humans", topics.humans, AGENTS), ("robot", topics.robot, AGENT),
            ("gesture", topics.robot_gesture, "std_msgs/msg/UInt32"), ("odom", topics.odom, "nav_msgs/msg/Odometry"),
            ("tf", topics.tf, "tf2_msgs/msg/TFMessage"), ("markers", topics.agent_markers, markers.MARKER_ARRAY))}
        bt = connect(topics.bt, "std_msgs/msg/String") if trace.node_names else None
        human_goals = trace.meta.get("human_goals") if isinstance(trace.meta, dict) else None
        goal_poses = {name: [pose(store, g[0], g[1], 0.0) for g in (human_goals or {}).get(name, [])]
                      for name in trace.human_names}
        robot_goal_radius = float(trace.meta.get("robot_goal_radius", ROBOT_GOAL_TOLERANCE)) \
            if isinstance(trace.meta, dict) else ROBOT_GOAL_TOLERANCE
        last_gesture: int | None = None
        for k, stamp_ns in enumerate(ns):
            _step(store, options.flavour, conns, put, trace, k, stamp_ns, first, goal_poses, goal_pose,
                  robot_goal_radius)
            gesture = int(trace.robot_gesture[k])
            if gesture != last_gesture:  # the wrapper keeps the last value: publish changes only
                put(conns["gesture"], stamp_ns, store.types["std_msgs/msg/UInt32"](data=gesture))
                last_gesture = gesture
            if bt is not None:
                put(bt, stamp_ns, string(data=json.dumps({"action": trace.action[k].tolist(),
                                                          "succeeded": trace.succeeded[k].tolist()})))
            if k % max(1, options.markers_every) == 0:
                put(conns["markers"], stamp_ns, markers.agent_markers(store, trace, k, stamp_ns))


def _step(store: Any, flavour: Flavour, conns: dict, put: Any, trace: Trace, k: int, stamp_ns: int, first: int,
          goal_poses: dict, goal_pose: Any, robot_goal_radius: float) -> None:
    types = store.types
    robot = trace.robot[k]
    put(conns["robot"], stamp_ns, _agent(
        store, flavour, ident=ROBOT_AGENT_ID, kind=ROBOT, name="robot", behavior=BEH_REGULAR, group=-1, state=robot,
        radius=trace.robot_radius, bstate=0, gesture=int(trace.robot_gesture[k]),
        goals=[goal_pose] if goal_pose is not None else [], goal_radius=robot_goal_radius, desired=0.0))
    agents = []
    for i, name in enumerate(trace.human_names):
        agent_id = int(name.removeprefix("human")) - 1 if name.removeprefix("human").isdigit() else i
        behavior = FIRST_LLM_BEHAVIOR + agent_id if flavour == "socrates" else BEH_REGULAR
        agents.append(_agent(
            store, flavour, ident=agent_id + first, kind=PERSON, name=name, behavior=behavior,
            group=int(trace.group_ids[i]), state=trace.humans[k, i], radius=float(trace.human_radii[i]),
            bstate=int(trace.behavior_state[k, i]), gesture=int(trace.human_gesture[k, i]),
            goals=goal_poses.get(name, []), goal_radius=PERSON_GOAL_RADIUS, skin=agent_id % 9))
    put(conns["humans"], stamp_ns, types[AGENTS](header=header(store, stamp_ns), agents=agents))
    yaw = float(robot[YAW])
    c, s = math.cos(yaw), math.sin(yaw)  # odometry twist is in the robot's frame (REP 105)
    body = twist(store, c * robot[VX] + s * robot[VY], -s * robot[VX] + c * robot[VY], robot[OMEGA])
    cov = np.zeros(36, dtype=np.float64)
    put(conns["odom"], stamp_ns, types["nav_msgs/msg/Odometry"](
        header=header(store, stamp_ns), child_frame_id="base_link",
        pose=types["geometry_msgs/msg/PoseWithCovariance"](pose=pose(store, robot[X], robot[Y], yaw), covariance=cov),
        twist=types["geometry_msgs/msg/TwistWithCovariance"](twist=body, covariance=cov)))
    v3 = types["geometry_msgs/msg/Vector3"]
    transform = types["geometry_msgs/msg/Transform"](
        translation=v3(x=float(robot[X]), y=float(robot[Y]), z=0.0), rotation=pose(store, 0, 0, yaw).orientation)
    put(conns["tf"], stamp_ns, types["tf2_msgs/msg/TFMessage"](transforms=[types["geometry_msgs/msg/TransformStamped"](
        header=header(store, stamp_ns), child_frame_id="base_link", transform=transform)]))
