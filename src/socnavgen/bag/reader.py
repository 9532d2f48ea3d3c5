"""Read a ROS 2 bag (rosbag2 folder, .mcap or .db3) of a HuNavSim run: the states HuNavSim's evaluator
records (hunav_msgs/Agents on the human topic, hunav_msgs/Agent on the robot topic, PoseStamped goals),
the robot's gesture as the SocRATES wrapper receives it, and what socnavgen's own bags add. Every way a bag
can be unusable ends in one `BagError` naming the file and what to do; nothing here knows about runs
(`to_trace` maps agents to humans and checks the recording against the run)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from rosbags.rosbag2 import Reader
from rosbags.rosbag2.errors import ReaderError
from rosbags.serde import SerdeError
from rosbags.typesys import TypesysError, get_types_from_msg
from rosbags.typesys.store import Typestore

from socnavgen.bag.types import AGENT, AGENTS, FLAVOURS, Flavour, store_with, typestore, yaw_of
from socnavgen.errors import InputFileError
from socnavgen.safeio import JSONLimitError, parse_json_text

MAX_STATE_MESSAGES = 4_000_000  # human or robot states: over an hour at HuNavSim's 1 kHz
MAX_MESSAGE_BYTES = 16 * 1024 * 1024  # one serialized message
MAX_AGENTS = 1024  # agents in one Agents message
RADIUS_DIGITS = 6  # radii are float32 in hunav_msgs: 0.4 arrives as 0.40000000596; they are configured values


class BagError(InputFileError):
    """The bag cannot be read, or is not a recording of this run."""


@dataclass
class ReadTopics:
    """Which topics hold what (names as recorded; a missing leading slash is tolerated)."""

    humans: str = "/human_states"
    robot: str = "/robot_states"
    goal: str = "/goal_pose"
    robot_gesture: str = "/robot_gesture"
    meta: str = "/socnavgen/meta"
    bt: str = "/socnavgen/bt"


@dataclass
class AgentState:
    ident: int
    name: str
    group: int
    radius: float
    state: tuple[float, float, float, float, float, float]  # x, y, yaw, vx, vy, omega
    behavior_state: int
    gesture: int


@dataclass
class Recording:
    """The decoded messages, in log order, before any mapping or resampling."""

    path: Path
    flavour: str  # socrates | hunav | "<flavour> (the bag's own definition)"
    human_log: list[int] = field(default_factory=list)  # log time (ns) of each human_states message
    human_stamp: list[int] = field(default_factory=list)  # its header stamp (ns; 0 when unset)
    humans: list[list[AgentState]] = field(default_factory=list)
    robot_log: list[int] = field(default_factory=list)
    robots: list[AgentState] = field(default_factory=list)
    gesture_log: list[int] = field(default_factory=list)
    gestures: list[int] = field(default_factory=list)
    goal: tuple[float, float] | None = None
    meta: dict | None = None
    bt_log: list[int] = field(default_factory=list)
    bt: list[dict] = field(default_factory=list)
    topics: dict[str, str] = field(default_factory=dict)  # role -> topic actually read


def _bag_error(path: Path, exc: BaseException) -> BagError:
    text = str(exc)
    if "Unrecognized storage format" in text:
        return BagError(f"not a ROS 2 bag (a {path.suffix or 'file'} without a storage plugin)", file=path,
                        hint="pass a rosbag2 folder, a .mcap or a .db3 file")
    if "end magic" in text or "magic is invalid" in text and path.suffix == ".mcap":
        return BagError("the MCAP file is truncated or damaged (it has no valid end; was the recording killed "
                        "before it closed?)", file=path,
                        hint="recover what it holds with `mcap recover FILE -o fixed.mcap` (the mcap CLI) and "
                             "pass the recovered file")
    if "malformed" in text or "missing tables" in text or "not a database" in text:
        return BagError(f"the sqlite3 bag is truncated or damaged ({text})", file=path,
                        hint="salvage it with `sqlite3 FILE .recover | sqlite3 fixed.db3`, or record again")
    if "metadata" in text.lower() or "yaml" in text.lower():
        return BagError(f"the bag folder's metadata.yaml is unusable ({text})", file=path,
                        hint="regenerate it with `ros2 bag reindex DIR`, or pass the .mcap / .db3 file itself")
    return BagError(f"not a readable ROS 2 bag ({text[:300]})", file=path,
                    hint="pass a rosbag2 folder, a .mcap or a .db3 file")


def _norm(topic: str) -> str:
    return "/" + topic.strip().lstrip("/")


def _find(reader: Reader, path: Path, role: str, topic: str, msgtype: str, required: bool) -> Any:
    """The connection of `topic` (checked to carry `msgtype`), None when optional and absent."""
    wanted = _norm(topic)
    matches = [c for c in reader.connections if _norm(c.topic) == wanted]
    if not matches:
        if not required:
            return None
        same_type = sorted({c.topic for c in reader.connections if c.msgtype == msgtype})
        listing = ", ".join(f"{c.topic} ({c.msgtype})" for c in reader.connections) or "no topic at all"
        hint = (f"pass --{role}-topic {same_type[0]}" if same_type else
                "record HuNavSim's states: ros2 bag record /human_states /robot_states /goal_pose /robot_gesture")
        raise BagError(f"the bag has no {wanted} topic ({msgtype}); it has {listing}", file=path, hint=hint)
    conn = matches[0]
    if conn.msgtype != msgtype:
        raise BagError(f"{conn.topic} carries {conn.msgtype}, not {msgtype}", file=path,
                       hint=f"name the topic that carries {msgtype} with --{role}-topic")
    return conn


def _bag_types(conn: Any) -> dict[str, Any] | None:
    """hunav_msgs definitions the bag carries itself (MCAP always does; sqlite3 bags from Iron on)."""
    data = getattr(conn.msgdef, "data", "") or ""
    if getattr(conn.msgdef.format, "name", "") != "MSG" or not data.strip():
        return None
    try:
        types = get_types_from_msg(data, conn.msgtype)
    except (TypesysError, ValueError, RecursionError):
        return None
    return {k: v for k, v in types.items() if k.startswith("hunav_msgs/")}


def _choose_store(reader: Reader, path: Path, humans: Any, robot: Any, forced: str) -> tuple[Typestore, str]:
    """The bag's own hunav_msgs when it carries them, else the shipped flavour whose definition decodes the
    first human and robot messages (the SocRATES fork's Agent has two more fields than upstream's)."""
    if forced == "auto":
        own: dict[str, Any] = {}
        for conn in (humans, robot):
            own.update(_bag_types(conn) or {})
        if AGENT in own and AGENTS in own:
            kind = "socrates" if any(f[0] == "gesture" for f in own[AGENT][1]) else "hunav"
            try:
                return store_with(own), f"{kind} (the bag's own definition)"
            except (TypesysError, ValueError):
                pass
    candidates: tuple[Flavour, ...] = FLAVOURS if forced == "auto" else (forced,)  # type: ignore[assignment]
    firsts = {}
    for conn in (humans, robot):
        for _, _, raw in reader.messages(connections=[conn]):
            firsts[conn.msgtype] = bytes(raw)
            break
    for flavour in candidates:
        store = typestore(flavour)
        try:
            for msgtype, raw in firsts.items():
                store.deserialize_cdr(raw, msgtype)
        except (SerdeError, ValueError, IndexError, OverflowError, MemoryError):
            continue
        return store, flavour
    tried = " nor ".join(f"the {f} hunav_msgs" for f in candidates)
    raise BagError(f"the messages on {humans.topic} / {robot.topic} decode with {tried}", file=path,
                   hint="the bag was recorded with other hunav_msgs definitions; --hunav-msgs socrates|hunav "
                        "forces one (docs/verify.md)")


def _agent(msg: Any, topic: str, path: Path) -> AgentState:
    p = msg.position
    yaw = yaw_of(p.orientation, msg.yaw)
    values = (float(p.position.x), float(p.position.y), yaw, float(msg.velocity.linear.x),
              float(msg.velocity.linear.y), float(msg.velocity.angular.z))
    if not all(math.isfinite(v) and abs(v) < 1e7 for v in values):
        raise BagError(f"agent {msg.id} on {topic} has a non-finite or absurd pose or velocity {values}", file=path,
                       hint="the recording is damaged")
    radius = round(float(msg.radius), RADIUS_DIGITS)
    return AgentState(ident=int(msg.id), name=str(msg.name)[:64], group=int(msg.group_id),
                      radius=radius if math.isfinite(radius) else 0.0, state=values,
                      behavior_state=int(msg.behavior_state), gesture=int(getattr(msg, "gesture", 0)))


def _json(raw_text: str, topic: str, path: Path) -> Any:
    try:
        return parse_json_text(raw_text)
    except (JSONLimitError, ValueError, RecursionError) as exc:
        raise BagError(f"{topic} holds a message that is not JSON ({str(exc)[:120]})", file=path,
                       hint=f"record without {topic}, or write the bag again with `socnavgen simulate --bag`") from None


def read_recording(path: Path | str, topics: ReadTopics | None = None, *, hunav_msgs: str = "auto") -> Recording:
    """Decode the relevant topics of the bag at `path` (nothing else is deserialized)."""
    path = Path(path)
    topics = topics or ReadTopics()
    if not path.exists():
        raise BagError("bag not found", file=path, hint="pass a rosbag2 folder, a .mcap or a .db3 file")
    try:
        with Reader(path) as reader:
            return _read(reader, path, topics, hunav_msgs)
    except BagError:
        raise
    except (ReaderError, OSError, KeyError, AssertionError, EOFError, ValueError) as exc:
        raise _bag_error(path, exc) from None
    except (SerdeError, TypesysError) as exc:
        raise BagError(f"a message of the bag cannot be decoded ({str(exc)[:200]})", file=path,
                       hint="the recording is damaged, or --hunav-msgs names the wrong definitions") from None


def _read(reader: Reader, path: Path, topics: ReadTopics, forced: str) -> Recording:
    humans = _find(reader, path, "humans", topics.humans, AGENTS, True)
    robot = _find(reader, path, "robot", topics.robot, AGENT, True)
    optional = {"goal": _find(reader, path, "goal", topics.goal, "geometry_msgs/msg/PoseStamped", False),
                "robot_gesture": _find(reader, path, "robot-gesture", topics.robot_gesture, "std_msgs/msg/UInt32",
                                       False),
                "meta": _find(reader, path, "meta", topics.meta, "std_msgs/msg/String", False),
                "bt": _find(reader, path, "bt", topics.bt, "std_msgs/msg/String", False)}
    store, flavour = _choose_store(reader, path, humans, robot, forced)
    rec = Recording(path=path, flavour=flavour,
                    topics={"humans": humans.topic, "robot": robot.topic,
                            **{k: c.topic for k, c in optional.items() if c is not None}})
    conns = [humans, robot, *(c for c in optional.values() if c is not None)]
    for count, (conn, log_ns, raw) in enumerate(reader.messages(connections=conns), start=1):
        if len(raw) > MAX_MESSAGE_BYTES:
            raise BagError(f"a message on {conn.topic} is {len(raw)} bytes (more than {MAX_MESSAGE_BYTES})",
                           file=path, hint="this is not a HuNavSim state message; check the topic names")
        if count > 2 * MAX_STATE_MESSAGES:
            raise BagError(f"the bag holds more than {2 * MAX_STATE_MESSAGES} state messages", file=path,
                           hint="cut one episode out of it (ros2 bag convert / mcap filter) and pass that")
        msg: Any = store.deserialize_cdr(raw, conn.msgtype)  # a generated message class of conn.msgtype
        if conn is humans:
            if len(msg.agents) > MAX_AGENTS:
                raise BagError(f"a message on {conn.topic} lists {len(msg.agents)} agents", file=path,
                               hint=f"at most {MAX_AGENTS} are read")
            rec.human_log.append(int(log_ns))
            rec.human_stamp.append(int(msg.header.stamp.sec) * 1_000_000_000 + int(msg.header.stamp.nanosec))
            rec.humans.append([_agent(a, conn.topic, path) for a in msg.agents])
        elif conn is robot:
            rec.robot_log.append(int(log_ns))
            rec.robots.append(_agent(msg, conn.topic, path))
        elif conn is optional["robot_gesture"]:
            rec.gesture_log.append(int(log_ns))
            rec.gestures.append(int(msg.data))
        elif conn is optional["goal"]:
            rec.goal = (float(msg.pose.position.x), float(msg.pose.position.y))
        elif conn is optional["meta"]:
            meta = _json(msg.data, conn.topic, path)
            rec.meta = meta if isinstance(meta, dict) else None
        else:
            step = _json(msg.data, conn.topic, path)
            if isinstance(step, dict):
                rec.bt_log.append(int(log_ns))
                rec.bt.append(step)
    for conn, stamps in ((humans, rec.human_log), (robot, rec.robot_log)):
        if not stamps:
            raise BagError(f"{conn.topic} has no messages", file=path,
                           hint="was HuNavSim running while the bag recorded? (the evaluator's topics are "
                                "/human_states and /robot_states)")
    if rec.goal is not None and not all(math.isfinite(v) for v in rec.goal):
        rec.goal = None
    return rec


def gesture_series(values: list[int], log: list[int], at: np.ndarray) -> np.ndarray:
    """The last value published at or before each log time of `at` (0 before the first)."""
    if not values:
        return np.zeros(len(at), dtype=np.int64)
    idx = np.searchsorted(np.asarray(log, dtype=np.int64), at, side="right") - 1
    series = np.asarray(values, dtype=np.int64)[np.clip(idx, 0, None)]
    return np.where(idx >= 0, series, 0)


def bt_series(rec: Recording, at: np.ndarray, humans: int) -> tuple[np.ndarray, np.ndarray] | None:
    """(action, succeeded) per sample from socnavgen's /socnavgen/bt messages, None when absent or unusable."""
    if not rec.bt:
        return None
    try:
        action = np.asarray([m["action"] for m in rec.bt], dtype=np.int64)
        succeeded = np.asarray([m["succeeded"] for m in rec.bt], dtype=np.int64)
    except (KeyError, TypeError, ValueError, OverflowError):
        return None
    if action.shape != (len(rec.bt), humans) or succeeded.shape != action.shape:
        return None
    idx = np.clip(np.searchsorted(np.asarray(rec.bt_log, dtype=np.int64), at, side="right") - 1, 0, None)
    return action[idx].astype(np.int16), succeeded[idx]
