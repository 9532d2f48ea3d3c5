"""Serialising export output: YAML the ROS 2 loaders read, BT XML from parsed elements, and the
all-or-nothing, contained write of a whole export (the old folder or the new one, never a mix)."""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

import yaml

from socnavgen.atomic_files import replace_folder
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


def write_export(out_dir: Path | str, files: list[ExportedFile], *, force: bool = False) -> list[Path]:
    """Write the whole export or nothing: every path is checked first, the files are written into a
    temp folder beside out_dir, and that folder replaces out_dir in one rename (see atomic_files)."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputFileError("the output path exists and is not a folder", file=out, hint="choose a folder with -o")
    relative = [contained_path(out, f.path).relative_to(out.resolve()) for f in files]  # all checked first
    clashes = sorted({str(r) for r in relative if any(str(o).startswith(str(r) + "/") for o in relative)})
    if clashes:
        raise InputFileError(f"export paths clash: {', '.join(clashes)} is both a file and a folder", file=out)

    def fill(staging: Path) -> None:
        for f, rel in zip(files, relative, strict=True):
            atomic_write_text(staging / rel, f.text)

    replace_folder(out, fill, force=force)
    return [out.resolve() / rel for rel in relative]
