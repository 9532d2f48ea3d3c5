"""Message types of HuNavSim bags: the ROS 2 Humble standard messages (rosbags' store) plus HuNavSim's
`hunav_msgs` in one of two flavours, from the real definitions shipped in `msgs/` (see msgs/README.md).

`hunav`    upstream HuNavSim 1.x / 2.x: Agent has no gesture.
`socrates` the SocRATES fork: Agent adds `pause_nav` and `gesture` (what the fork's evaluator records).
"""

from __future__ import annotations

import math
from functools import cache
from importlib import resources
from typing import Any, Literal

from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

Flavour = Literal["socrates", "hunav"]
FLAVOURS: tuple[Flavour, ...] = ("socrates", "hunav")
AGENT = "hunav_msgs/msg/Agent"
AGENTS = "hunav_msgs/msg/Agents"
HUNAV_TYPES = (AGENT, AGENTS)


def msg_text(flavour: Flavour, name: str) -> str:
    """The shipped .msg file `name` (Agent, Agents) of a flavour."""
    return resources.files("socnavgen.bag").joinpath("msgs", flavour, f"{name}.msg").read_text(encoding="utf-8")


def hunav_types(flavour: Flavour) -> dict[str, Any]:
    types: dict[str, Any] = {}
    types.update(get_types_from_msg(msg_text(flavour, "Agent"), AGENT))
    types.update(get_types_from_msg(msg_text(flavour, "Agents"), AGENTS))
    return types


@cache
def typestore(flavour: Flavour) -> Typestore:
    """Humble's standard messages and hunav_msgs of `flavour` (built once per process; read only)."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    store.register(hunav_types(flavour))
    return store


def store_with(definitions: dict[str, Any]) -> Typestore:
    """Humble's standard messages plus type definitions a bag carries (its own hunav_msgs)."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    store.register(definitions)
    return store


# -- small builders shared by the writer and the tests -------------------------------------------------
def stamp(store: Typestore, nanoseconds: int) -> Any:
    return store.types["builtin_interfaces/msg/Time"](sec=int(nanoseconds // 1_000_000_000),
                                                       nanosec=int(nanoseconds % 1_000_000_000))


def header(store: Typestore, nanoseconds: int, frame: str = "map") -> Any:
    return store.types["std_msgs/msg/Header"](stamp=stamp(store, nanoseconds), frame_id=frame)


def quaternion(store: Typestore, yaw: float) -> Any:
    return store.types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))


def point(store: Typestore, x: float, y: float, z: float = 0.0) -> Any:
    return store.types["geometry_msgs/msg/Point"](x=float(x), y=float(y), z=float(z))


def pose(store: Typestore, x: float, y: float, yaw: float, z: float = 0.0) -> Any:
    return store.types["geometry_msgs/msg/Pose"](position=point(store, x, y, z), orientation=quaternion(store, yaw))


def twist(store: Typestore, vx: float, vy: float, omega: float) -> Any:
    v3 = store.types["geometry_msgs/msg/Vector3"]
    return store.types["geometry_msgs/msg/Twist"](linear=v3(x=float(vx), y=float(vy), z=0.0),
                                                  angular=v3(x=0.0, y=0.0, z=float(omega)))


def yaw_of(orientation: Any, fallback: float) -> float:
    """Yaw of a geometry_msgs/Quaternion (float64, so exact), or `fallback` (Agent.yaw, float32) when the
    quaternion is not a unit rotation about z (some publishers leave it zero)."""
    x, y, z, w = (float(orientation.x), float(orientation.y), float(orientation.z), float(orientation.w))
    norm = x * x + y * y + z * z + w * w
    if not math.isfinite(norm) or abs(norm - 1.0) > 1e-3:
        return float(fallback)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
