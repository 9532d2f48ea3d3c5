"""Defensive file I/O shared by every stage: size limits, file:line on parse errors, atomic writes,
and paths that cannot leave their folder."""

from __future__ import annotations

import json
import os
import re
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import yaml

from socnavgen.errors import InputFileError

if TYPE_CHECKING:
    from pydantic import BaseModel

M = TypeVar("M", bound="BaseModel")

MAX_TEXT_BYTES = 8 * 1024 * 1024  # JSON / YAML / XML a user or a model can hand us
MAX_IMAGE_BYTES = 64 * 1024 * 1024
ORDINARY_FILE_MODE = 0o666  # what open() asks for; the process umask then removes bits (usually -> 0644)


def read_text_limited(path: Path, limit: int = MAX_TEXT_BYTES) -> str:
    path = Path(path)
    if not path.is_file():
        raise InputFileError("file not found", file=path, hint="check the path")
    size = path.stat().st_size
    if size > limit:
        raise InputFileError(f"file is {size} bytes, more than the {limit} allowed", file=path,
                             hint="is this the right file?")
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise InputFileError(f"not UTF-8 text ({exc.reason} at byte {exc.start})", file=path) from exc


def load_json_file(path: Path, limit: int = MAX_TEXT_BYTES) -> Any:
    text = read_text_limited(path, limit)
    try:
        return parse_json_text(text)
    except json.JSONDecodeError as exc:
        raise InputFileError(f"malformed JSON: {exc.msg} (column {exc.colno})", file=path, line=exc.lineno,
                             hint="fix the JSON syntax at that line") from exc
    except JSONLimitError as exc:
        raise InputFileError(f"refused: {exc}", file=path, hint="is this the right file?") from exc


def load_yaml_file(path: Path, limit: int = MAX_TEXT_BYTES) -> Any:
    return parse_yaml_text(read_text_limited(path, limit), path)


def parse_yaml_text(text: str, file: Path | str) -> Any:
    """yaml.safe_load with one message naming `file` for everything it can raise: malformed YAML (with its
    line), nesting too deep, an integer of thousands of digits (Python refuses to read it)."""
    try:
        return yaml.safe_load(text)
    except RecursionError as exc:
        raise InputFileError("refused: YAML nested too deeply", file=file, hint="is this the right file?") from exc
    except ValueError as exc:  # int() of more than 4300 digits, raised while constructing the value
        raise InputFileError("refused: a number with thousands of digits", file=file,
                             hint="is this the right file? (keys and values are names and ordinary numbers)") from exc
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise InputFileError(f"malformed YAML: {problem}", file=file, line=line,
                             hint="fix the YAML syntax at that line") from exc


def _umask() -> int:
    """The process umask (reading it means setting it; restored at once)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def ordinary_mode() -> int:
    """The mode an ordinary open() gives a new file (0666 minus the umask): temp files (mkstemp: 0600) get it
    before they are renamed into place."""
    return ORDINARY_FILE_MODE & ~_umask()


def atomic_write_bytes(path: Path, data: bytes) -> None:
    """Write to a temp file in the same folder and rename: a crash never leaves a half file.

    mkstemp creates the temp file 0600; it gets the mode an ordinary open() would give (0666 minus
    the umask) before the rename, so a ROS container running as another user can read exports."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, ordinary_mode())
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_text(path: Path, text: str) -> None:
    atomic_write_bytes(path, text.encode("utf-8"))


def atomic_write_json(path: Path, data: Any, indent: int = 2) -> None:
    atomic_write_text(path, json.dumps(data, indent=indent, ensure_ascii=False) + "\n")


def contained_path(base: Path, relative: str | Path) -> Path:
    """Resolve `relative` under `base`, refusing anything that escapes it (.., absolute, symlinks)."""
    base = Path(base).resolve()
    rel = Path(relative)
    if rel.is_absolute():
        raise InputFileError(f"absolute path {str(relative)!r} not allowed here", hint="use a path relative to the folder")
    target = (base / rel).resolve()
    if target != base and base not in target.parents:
        raise InputFileError(f"path {str(relative)!r} leaves {base}", hint="keep files inside the folder")
    return target


def load_model_file(path: Path, model: type[M], *, hint: str | None = None) -> M:
    """A JSON or YAML file (by suffix) validated into `model`; the first schema error names its field."""
    from pydantic import ValidationError

    path = Path(path)
    data = load_yaml_file(path) if path.suffix.lower() in (".yaml", ".yml") else load_json_file(path)
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(p) for p in first["loc"]) or "(top level)"
        raise InputFileError(f"{where}: {first['msg']}", file=path, hint=hint) from exc


# ---- limits on what JSON and images may ask of us -----------------------------------------------
MAX_JSON_DEPTH = 200  # far deeper than any file of ours; json's C parser recurses, deep input crashes it
MAX_INT_DIGITS = 100  # a coordinate or a count never needs more; Python refuses > 4300 with a ValueError

_JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.DOTALL)


class JSONLimitError(ValueError):
    """JSON text breaks a resource limit (nesting depth, integer size)."""


def json_depth(text: str) -> int:
    """Deepest bracket nesting of JSON text, strings ignored (linear time, no recursion)."""
    import numpy as np

    skeleton = _JSON_STRING.sub("", text).encode("utf-8", "ignore")
    raw = np.frombuffer(skeleton, dtype=np.uint8)
    steps = (np.isin(raw, (ord("["), ord("{"))).astype(np.int32)
             - np.isin(raw, (ord("]"), ord("}"))).astype(np.int32))
    return int(np.cumsum(steps).max(initial=0))


def _bounded_int(literal: str) -> int:
    if len(literal.lstrip("-")) > MAX_INT_DIGITS:
        raise JSONLimitError(f"an integer of {len(literal.lstrip('-'))} digits (at most {MAX_INT_DIGITS} allowed)")
    return int(literal)


def parse_json_text(text: str, *, max_depth: int = MAX_JSON_DEPTH) -> Any:
    """json.loads with limits: nesting deeper than `max_depth` and huge integers raise JSONLimitError
    (never RecursionError or Python's 4300-digit ValueError); syntax errors raise json.JSONDecodeError."""
    depth = json_depth(text)
    if depth > max_depth:
        raise JSONLimitError(f"JSON nested {depth} levels deep (at most {max_depth} allowed)")
    try:
        return json.loads(text, parse_int=_bounded_int)
    except RecursionError as exc:  # a depth the scan missed (should not happen): still one message
        raise JSONLimitError("JSON nested too deeply") from exc


def check_image_pixels(width: int, height: int, file: Path | str | None = None) -> None:
    """Refuse an image over the pixel budget from its header, before decoding (a 200 KB PNG can
    declare 13000 x 13000 px and take gigabytes once decoded)."""
    from socnavgen.limits import MAX_IMAGE_PIXELS

    if width * height > MAX_IMAGE_PIXELS:
        raise InputFileError(f"image is {width} x {height} px, more than the {MAX_IMAGE_PIXELS} pixels allowed",
                             file=file, hint="scale the map down (a few thousand pixels a side is plenty)")
