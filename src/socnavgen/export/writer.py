"""Serialising export output: YAML the ROS 2 loaders read, BT XML from parsed elements, and the
all-or-nothing, contained write of a whole export that replaces only what an earlier export wrote."""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

import yaml

from socnavgen.atomic_files import EXPORT_MARKER, write_files_atomically
from socnavgen.bt.tree import BTElement
from socnavgen.errors import InputFileError, SocnavgenError
from socnavgen.export.models import ExportedFile, RobotExport
from socnavgen.safeio import contained_path, parse_json_text, read_text_limited

MARKER_HEADER = "written by socnavgen export: the files below (sha256); a re-export replaces only these"
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


def _files_in(out: Path) -> set[str]:
    """Every file (or symlink) under `out`, relative, the marker left out; symlinked folders are not entered."""
    found: set[str] = set()
    for root, dirs, names in os.walk(out, followlinks=False):
        base = Path(root)
        found.update(str((base / n).relative_to(out)) for n in names)
        found.update(str((base / d).relative_to(out)) for d in dirs if (base / d).is_symlink())
    found.discard(EXPORT_MARKER)
    return found


def _digest(path: Path) -> str | None:
    if path.is_symlink() or not path.is_file():
        return None
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _marker(out: Path) -> dict[str, str] | None:
    """What an earlier export wrote: relative path -> sha256. None without a marker; {} for a marker of an
    older socnavgen (it listed nothing: then no file counts as ours except those this export rewrites)."""
    path = out / EXPORT_MARKER
    if path.is_symlink() or not path.is_file():
        return None
    try:
        data = parse_json_text(read_text_limited(path).split("\n", 1)[1])
    except (SocnavgenError, ValueError, IndexError, UnicodeDecodeError):
        return {}
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, dict):
        return {}
    return {str(k): str(v) for k, v in files.items() if isinstance(k, str) and isinstance(v, str)}


def _marker_text(written: dict[str, bytes]) -> str:
    listing = {rel: hashlib.sha256(data).hexdigest() for rel, data in sorted(written.items())}
    return MARKER_HEADER + "\n" + json.dumps({"format": 1, "files": listing}, indent=1) + "\n"


@dataclass
class WriteResult:
    written: list[Path]
    kept: list[str]  # files in the folder that no export wrote: left untouched
    removed: list[str]  # files of the earlier export that this one no longer has


def write_export(out_dir: Path | str, files: list[ExportedFile], *, force: bool = False) -> WriteResult:
    """Write an export into `out_dir`, touching only what socnavgen export wrote there.

    The folder's marker (EXPORT_MARKER) lists every file an export wrote with its sha256. A re-export
    replaces those files (unchanged since) and removes the ones it no longer has; every other file stays.
    A non-empty folder without a marker is refused unless `force`, and even then nothing in it is replaced
    or removed: an export that would overwrite a file it did not write (or one changed since) is refused,
    listing them. The new files are written all together or not at all (atomic_files)."""
    out = Path(out_dir)
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise InputFileError("the output path exists and is not a folder", file=out, hint="choose a folder with -o")
    relative = [contained_path(out, f.path).relative_to(out.resolve()) for f in files]  # all checked first
    clashes = sorted({str(r) for r in relative if any(str(o).startswith(str(r) + "/") for o in relative)})
    if clashes:
        raise InputFileError(f"export paths clash: {', '.join(clashes)} is both a file and a folder", file=out)
    new = {str(r): f.text.encode("utf-8") for f, r in zip(files, relative, strict=True)}
    existing = _files_in(out) if out.is_dir() else set()
    marker = _marker(out) if out.is_dir() else None
    if existing and marker is None and not force:
        raise InputFileError("the output folder is not empty and was not written by socnavgen export", file=out,
                             hint="choose a new or empty folder, or pass --force to write beside its files "
                                  "(they are never replaced or deleted)")
    if marker:
        ours = {rel for rel, sha in marker.items() if rel in existing and _digest(out / rel) == sha}
    else:  # an older marker lists nothing: its files are known only by the names this export writes again
        ours = existing & set(new) if marker == {} else set()
    foreign = existing - ours
    blocked = sorted(rel for rel in foreign if rel in new or any(rel.startswith(n + "/") or n.startswith(rel + "/")
                                                                  for n in new))
    if blocked:
        shown = ", ".join(blocked[:10]) + (f" and {len(blocked) - 10} more" if len(blocked) > 10 else "")
        raise InputFileError(f"the export would replace file(s) it did not write (or that changed since it wrote "
                             f"them): {shown}", file=out,
                             hint="move them out of the folder, or export to another folder (-o)")
    targets = {out / rel: data for rel, data in new.items()}
    targets[out / EXPORT_MARKER] = _marker_text(new).encode("utf-8")
    created = sorted({d for t in targets for d in (t.parent, *t.parent.parents)
                      if (d == out or out in d.parents) and not d.exists()}, key=lambda d: len(d.parts), reverse=True)
    try:
        write_files_atomically(targets)
    except BaseException:
        for folder in created:  # folders this export made and left empty go again: nothing is left behind
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise
    removed = sorted(ours - set(new))
    for rel in removed:
        (out / rel).unlink(missing_ok=True)
        parent = (out / rel).parent
        while parent != out and parent.is_dir() and not any(parent.iterdir()):
            parent.rmdir()
            parent = parent.parent
    return WriteResult(written=[out.resolve() / r for r in relative], kept=sorted(foreign), removed=removed)
