"""The simulation trace: per step poses, velocities, BT activity and gestures, stored columnar
(compressed .npz) so metrics, plots, animation and the verifier read one format."""

from __future__ import annotations

import io
import json
import math
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from socnavgen.errors import InputFileError
from socnavgen.safeio import atomic_write_bytes, parse_json_text

# Columns of `robot` and `humans` state arrays.
X, Y, YAW, VX, VY, OMEGA = range(6)
STATE_COLUMNS = ("x", "y", "yaw", "vx", "vy", "omega")


# A person's behavior code, as the simulator keeps it (people's `behavior`) and the trace records it (behavior_state)
REGULAR_BEHAVIOR = 0  # walking their own way (RegularNav) or standing
ROBOT_BEHAVIOR = 1  # doing something about the robot (following, looking at, blocking, avoiding it)
GIVE_WAY_BEHAVIOR = 2  # stepping aside for it (a tree's GiveWaytoRobot, or making room)

@dataclass
class Trace:
    dt: float
    t: np.ndarray  # (T,) seconds
    robot: np.ndarray  # (T, 6) x, y, yaw, vx, vy, omega (world frame)
    humans: np.ndarray  # (T, H, 6)
    human_names: list[str]  # human1..humanH (agent id = index)
    group_ids: list[int]  # (H,)
    human_radii: np.ndarray  # (H,)
    robot_radius: float
    node_names: list[str]  # library leaf names indexed by `action` and the bits of `succeeded`
    action: np.ndarray  # (T, H) int16: index into node_names of the action executed this step, -1 none
    succeeded: np.ndarray  # (T, H) int64 bitmask over node_names: leaves that returned SUCCESS this step
    human_gesture: np.ndarray  # (T, H) int8
    robot_gesture: np.ndarray  # (T,) int8
    behavior_state: np.ndarray  # (T, H) int8: REGULAR_BEHAVIOR, ROBOT_BEHAVIOR or GIVE_WAY_BEHAVIOR
    robot_goal: tuple[float, float] | None = None
    robot_waypoints: list[tuple[float, float]] = field(default_factory=list)
    end_reason: str = ""
    meta: dict = field(default_factory=dict)

    @property
    def steps(self) -> int:
        return int(self.t.shape[0])

    def node_index(self, name: str) -> int:
        return self.node_names.index(name)

    def executed(self, human: int, name: str) -> np.ndarray:
        """(T,) bool: steps on which human executed action `name`."""
        if name not in self.node_names:
            return np.zeros(self.steps, dtype=bool)
        return self.action[:, human] == self.node_index(name)

    def fired(self, human: int, name: str) -> np.ndarray:
        """(T,) bool: steps on which leaf `name` returned SUCCESS for this human."""
        if name not in self.node_names:
            return np.zeros(self.steps, dtype=bool)
        bit = np.int64(1) << np.int64(self.node_index(name))
        return (self.succeeded[:, human] & bit) != 0

    def save(self, path: Path) -> None:
        meta = {
            "dt": self.dt, "human_names": self.human_names, "group_ids": self.group_ids,
            "robot_radius": self.robot_radius, "node_names": self.node_names,
            "robot_goal": self.robot_goal, "robot_waypoints": self.robot_waypoints,
            "end_reason": self.end_reason, "meta": self.meta,
        }
        atomic_write_bytes(Path(path), npz_bytes({
            "t": self.t, "robot": self.robot, "humans": self.humans, "human_radii": self.human_radii,
            "action": self.action, "succeeded": self.succeeded, "human_gesture": self.human_gesture,
            "robot_gesture": self.robot_gesture, "behavior_state": self.behavior_state,
            "meta": np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)}))

    @classmethod
    def load(cls, path: Path) -> Trace:
        """Read a trace written by `save`, refusing damaged or hostile files with one message: sizes
        are checked from the zip and .npy headers before anything is decompressed, then every array's
        shape against the others and the metadata's types."""
        path = Path(path)
        try:
            arrays, meta = _read_checked(path)
            return _from_parts(arrays, meta)
        except TraceError as exc:
            raise InputFileError(f"not a usable trace: {exc}", file=path,
                                 hint="re-run `socnavgen simulate` to write it again") from None
        except (OSError, ValueError, KeyError, TypeError, EOFError, zipfile.BadZipFile) as exc:
            raise InputFileError(f"not a usable trace ({type(exc).__name__}: {str(exc)[:200]})", file=path,
                                 hint="re-run `socnavgen simulate` to write it again") from None


MAX_TRACE_BYTES = 512 * 1024 * 1024  # decompressed size of all arrays of one trace (a 1-hour, 64-human run fits)
ARRAYS = ("t", "robot", "humans", "human_radii", "action", "succeeded", "human_gesture", "robot_gesture",
          "behavior_state", "meta")

HEADER_READERS = {(1, 0): np.lib.format.read_array_header_1_0, (2, 0): np.lib.format.read_array_header_2_0}


NPZ_LEVEL = 1  # deflate level of our .npz files: ~2x faster to write than np.savez_compressed's 6, ~2 % larger


def npz_bytes(arrays: dict[str, np.ndarray], level: int = NPZ_LEVEL) -> bytes:
    """The bytes np.savez_compressed would write for `arrays` (a zip of .npy files that numpy.load reads), at
    deflate `level` (a campaign writes one file per episode)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=level) as archive:
        for name, array in arrays.items():
            with archive.open(f"{name}.npy", "w", force_zip64=True) as f:
                np.lib.format.write_array(f, np.asanyarray(array), allow_pickle=False)
    return buf.getvalue()


class TraceError(ValueError):
    """The trace file is damaged or not ours."""


def _read_checked(path: Path) -> tuple[dict[str, np.ndarray], dict]:
    if not path.is_file():
        raise InputFileError("trace not found", file=path, hint="run `socnavgen simulate` first")
    with zipfile.ZipFile(path) as archive:
        members = {info.filename.removesuffix(".npy"): info for info in archive.infolist()}
        missing = [name for name in ARRAYS if name not in members]
        if missing:
            raise TraceError(f"missing array(s) {', '.join(missing)}")
        declared = sum(members[name].file_size for name in ARRAYS)
        if declared > MAX_TRACE_BYTES:
            raise TraceError(f"it unpacks to {declared} bytes, more than the {MAX_TRACE_BYTES} allowed")
        arrays = {}
        for name in ARRAYS:
            with archive.open(members[name]) as fh:
                version = np.lib.format.read_magic(fh)
                if version not in HEADER_READERS:
                    raise TraceError(f"array {name} has .npy format version {version}")
                shape, _, dtype = HEADER_READERS[version](fh)  # the header only: nothing decompressed yet
                if dtype.hasobject:
                    raise TraceError(f"array {name} holds Python objects")
                nbytes = int(np.prod(shape, dtype=np.float64)) * dtype.itemsize
                if nbytes > members[name].file_size:
                    raise TraceError(f"array {name} claims {nbytes} bytes in a {members[name].file_size}-byte entry")
            with archive.open(members[name]) as fh:
                arrays[name] = np.lib.format.read_array(fh, allow_pickle=False)
    try:
        meta = parse_json_text(bytes(arrays.pop("meta")).decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as exc:
        raise TraceError(f"its metadata is not JSON ({exc})") from None
    return arrays, _checked_meta(meta)


def _checked_meta(meta: object) -> dict:
    if not isinstance(meta, dict):
        raise TraceError("its metadata is not a JSON object")
    kinds: dict[str, type | tuple[type, ...]] = {"dt": (int, float), "human_names": list, "group_ids": list, "robot_radius": (int, float),
             "node_names": list, "robot_waypoints": list, "end_reason": str, "meta": dict}
    for key, kind in kinds.items():
        if not isinstance(meta.get(key), kind) or isinstance(meta.get(key), bool):
            raise TraceError(f"metadata field {key!r} is missing or has the wrong type")
    if not (math.isfinite(meta["dt"]) and meta["dt"] > 0):
        raise TraceError("metadata dt must be a positive number")
    if not all(isinstance(n, str) for n in meta["human_names"] + meta["node_names"]):
        raise TraceError("human and node names must be strings")
    if len(meta["node_names"]) > 63:
        raise TraceError("more than 63 node names (the `succeeded` bitmask has 64 bits)")
    goal = meta.get("robot_goal")
    if goal is not None and not (isinstance(goal, list) and len(goal) == 2):
        raise TraceError("metadata robot_goal must be [x, y] or null")
    if not all(isinstance(w, list) and len(w) == 2 for w in meta["robot_waypoints"]):
        raise TraceError("metadata robot_waypoints must be [x, y] pairs")
    return meta


def _from_parts(a: dict[str, np.ndarray], meta: dict) -> Trace:
    steps, humans = a["t"].shape[0] if a["t"].ndim == 1 else -1, len(meta["human_names"])
    expected = {"t": (steps,), "robot": (steps, 6), "humans": (steps, humans, 6), "human_radii": (humans,),
                "action": (steps, humans), "succeeded": (steps, humans), "human_gesture": (steps, humans),
                "robot_gesture": (steps,), "behavior_state": (steps, humans)}
    for name, shape in expected.items():
        if a[name].shape != shape or a[name].dtype.kind not in "biuf":
            raise TraceError(f"array {name} has shape {a[name].shape} ({a[name].dtype}), expected {shape} numbers")
    if len(meta["group_ids"]) != humans:
        raise TraceError(f"{len(meta['group_ids'])} group ids for {humans} humans")
    goal = meta.get("robot_goal")
    return Trace(
        dt=float(meta["dt"]), t=a["t"], robot=a["robot"], humans=a["humans"], human_names=meta["human_names"],
        group_ids=meta["group_ids"], human_radii=a["human_radii"], robot_radius=float(meta["robot_radius"]),
        node_names=meta["node_names"], action=a["action"], succeeded=a["succeeded"],
        human_gesture=a["human_gesture"], robot_gesture=a["robot_gesture"], behavior_state=a["behavior_state"],
        robot_goal=tuple(goal) if goal else None, robot_waypoints=[tuple(w) for w in meta["robot_waypoints"]],
        end_reason=meta["end_reason"], meta=meta["meta"])
