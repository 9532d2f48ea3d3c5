"""Serialising export output: YAML the ROS 2 loaders read, BT XML from parsed elements, and the
atomic, contained write of a whole export (nothing is written until every file is ready)."""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

import yaml

from socnavgen.bt.tree import BTElement
from socnavgen.errors import InputFileError
from socnavgen.export.models import ExportedFile, RobotExport
from socnavgen.safeio import atomic_write_text, contained_path

COORD_DIGITS = 4  # 0.1 mm: far below map resolution, keeps the yaml readable


def metres(value: float) -> float:
    return round(float(value), COORD_DIGITS)


def dump_yaml(data: object) -> str:
    """Block-style YAML in the key order given (ROS 2 parameter files are order-insensitive, people are not)."""
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=False, allow_unicode=True, width=100)


def element_xml(elem: BTElement, level: int = 1, indent: str = "  ") -> str:
    """One element and its children as indented XML (attributes keep their order)."""
    pad = indent * level
    attrs = "".join(f" {k}={quoteattr(v)}" for k, v in elem.attrs.items())
    if not elem.children:
        return f"{pad}<{escape(elem.tag)}{attrs}/>\n"
    inner = "".join(element_xml(c, level + 1, indent) for c in elem.children)
    return f"{pad}<{escape(elem.tag)}{attrs}>\n{inner}{pad}</{escape(elem.tag)}>\n"


def robot_poses_yaml(robot: RobotExport) -> str:
    """The SocRATES wrapper's robot_poses.yaml: start pose and waypoints in metres, yaw toward the
    next waypoint; read by the nav2 waypoint follower and by a teleop script alike."""
    data = {
        "initial_pose": {"x": metres(robot.start.x), "y": metres(robot.start.y), "yaw": metres(robot.start.yaw)},
        "waypoints": [{"position": {"x": metres(w.x), "y": metres(w.y), "yaw": metres(w.yaw)}}
                      for w in robot.waypoints],
    }
    return dump_yaml(data)


def write_export(out_dir: Path | str, files: list[ExportedFile]) -> list[Path]:
    """Write every file under out_dir atomically; refuse any path that would leave it."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputFileError("the output path exists and is not a folder", file=out, hint="choose a folder with -o")
    targets = [contained_path(out, f.path) for f in files]  # all checked before anything is written
    out.mkdir(parents=True, exist_ok=True)
    for f, target in zip(files, targets, strict=True):
        atomic_write_text(target, f.text)
    return targets
