"""Paths and atomic reads/writes of a run folder (design contract: request.json, scenario.json,
paths.json, behaviors/<human>.xml, transcript.jsonl, manifest.json, sim/).

Every read goes through `contained_path`, so a symlink (a file, or the behaviors/ folder) that
leads out of the run folder is refused instead of followed. `lock()` makes one process the only
writer of a run folder at a time (the lock file sits beside the folder: RUN/../.RUN.socnavgen-lock).
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from pydantic import BaseModel

from socnavgen.errors import InputFileError
from socnavgen.run.models import Manifest, PathPlan, ScenarioProposal, ScenarioRequest, check_human_name
from socnavgen.run.spec import ScenarioSpec
from socnavgen.safeio import atomic_write_text, contained_path, load_model_file, read_text_limited

if TYPE_CHECKING:
    from socnavgen.location import Location

M = TypeVar("M", bound=BaseModel)
LOCATION_FILE = "location.yaml"
LOCK_SUFFIX = ".socnavgen-lock"
_HELD: dict[str, int] = {}  # lock file -> descriptor, for locks held until the process ends


@dataclass
class RunFolder:
    root: Path

    def __post_init__(self) -> None:
        self.root = Path(self.root)

    # -- well-known files --------------------------------------------------------------------
    @property
    def request_path(self) -> Path:
        return self.root / "request.json"

    @property
    def scenario_path(self) -> Path:
        return self.root / "scenario.json"

    @property
    def spec_path(self) -> Path:
        return self.root / "spec.json"

    @property
    def proposals_path(self) -> Path:
        return self.root / "proposals.json"

    @property
    def paths_path(self) -> Path:
        return self.root / "paths.json"

    @property
    def behaviors_dir(self) -> Path:
        return self.root / "behaviors"

    @property
    def transcript_path(self) -> Path:
        return self.root / "transcript.jsonl"

    @property
    def manifest_path(self) -> Path:
        return self.root / "manifest.json"

    @property
    def sim_dir(self) -> Path:
        return self.root / "sim"

    def require(self) -> None:
        """One clear error when the run folder does not exist (before any file of it is looked for)."""
        if not self.root.is_dir():
            what = "not a folder" if self.root.exists() else "no such run folder"
            raise InputFileError(what, file=self.root,
                                 hint="give a folder written by `socnavgen generate` or `socnavgen cards generate`")

    def behavior_path(self, human: str) -> Path:
        try:
            check_human_name(human)
        except ValueError as exc:
            raise InputFileError(str(exc), file=self.behaviors_dir) from None
        return contained_path(self.root, f"behaviors/{human}.xml")

    # -- locking -----------------------------------------------------------------------------
    @property
    def lock_path(self) -> Path:
        """Beside the folder, not in it: copies and listings of the run never see it."""
        root = self.root.resolve()
        return root.parent / f".{root.name}{LOCK_SUFFIX}"

    @contextlib.contextmanager
    def lock(self) -> Iterator[None]:
        """Hold the run folder for this process; a second writer is refused at once (never waits).

        An advisory flock: the kernel releases it when the process dies, so a crash never leaves a
        stale lock behind."""
        fd = self._acquire()
        try:
            yield
        finally:
            os.close(fd)  # closing releases the lock

    def hold_lock(self) -> None:
        """`lock()` for the rest of this process (a CLI command): released when the process ends.
        Idempotent within a process, so a program (or a test) may run several commands on one folder."""
        key = str(self.lock_path)
        if key not in _HELD:
            _HELD[key] = self._acquire()

    def _acquire(self) -> int:
        from socnavgen.locks import acquire

        self.root.parent.resolve().mkdir(parents=True, exist_ok=True)
        return acquire(self.lock_path, f"run folder {self.root}", "wait for it to finish, or write to another --out")

    # -- typed access ------------------------------------------------------------------------
    def _read(self, path: Path, model: type[M]) -> M:
        path = contained_path(self.root, path.relative_to(self.root))
        return load_model_file(path, model, hint="was this file edited by hand?")

    def _write(self, path: Path, value: BaseModel) -> None:
        atomic_write_text(path, value.model_dump_json(indent=2) + "\n")

    def read_request(self) -> ScenarioRequest:
        """request.json, with `location` resolved to an absolute folder when it can be found (it is stored
        relative to the run folder, so the run works from any directory and moves with its location)."""
        request = self._read(self.request_path, ScenarioRequest)
        found = self._find_location(request.location)
        return request.model_copy(update={"location": str(found)}) if found else request

    def write_request(self, value: ScenarioRequest) -> None:
        """Store the location relative to the run folder (absolute when there is no relative path)."""
        folder = Path(value.location)
        if (folder / LOCATION_FILE).is_file():
            try:
                stored = os.path.relpath(folder.resolve(), self.root.resolve())
            except ValueError:  # another drive: no relative path exists
                stored = str(folder.resolve())
            value = value.model_copy(update={"location": stored})
        self._write(self.request_path, value)

    def _find_location(self, stored: str) -> Path | None:
        """The folder request.json means: absolute; relative to the run folder (how it is written); or, for
        runs written before, relative to the current directory."""
        given = Path(stored)
        candidates = [given] if given.is_absolute() else [self.root / given, Path.cwd() / given]
        return next((c.resolve() for c in candidates if (c / LOCATION_FILE).is_file()), None)

    def location(self, override: Location | Path | str | None = None) -> Location:
        """THE resolver of a run's location: `override` (a loaded Location is passed through, a folder is
        loaded), else the folder request.json names. Load it once and pass the object on."""
        from socnavgen.errors import InputFileError
        from socnavgen.location import Location, load_location

        if isinstance(override, Location):
            return override
        if override is not None:
            return load_location(Path(override))
        if not self.request_path.is_file():
            raise InputFileError("no request.json: cannot tell which location this run uses", file=self.root,
                                 hint="pass --location DIR")
        stored = self._read(self.request_path, ScenarioRequest).location
        found = self._find_location(stored)
        if found is None:
            raise InputFileError(f"location folder {stored!r} of this run was not found (looked relative to the "
                                 "run folder and to the current directory)", file=self.request_path,
                                 hint="pass --location DIR to say where the location folder is now")
        return load_location(found)

    def read_scenario(self) -> ScenarioProposal:
        return self._read(self.scenario_path, ScenarioProposal)

    def write_scenario(self, value: ScenarioProposal) -> None:
        self._write(self.scenario_path, value)

    def read_spec(self) -> ScenarioSpec | None:
        """spec.json, or None for runs made before specs existed."""
        return self._read(self.spec_path, ScenarioSpec) if self.spec_path.is_file() else None

    def write_spec(self, value: ScenarioSpec) -> None:
        self._write(self.spec_path, value)

    def read_paths(self) -> PathPlan:
        return self._read(self.paths_path, PathPlan)

    def write_paths(self, value: PathPlan) -> None:
        self._write(self.paths_path, value)

    def read_manifest(self) -> Manifest:
        return self._read(self.manifest_path, Manifest)

    def write_manifest(self, value: Manifest) -> None:
        self._write(self.manifest_path, value)

    def read_behavior(self, human: str) -> str:
        return read_text_limited(self.behavior_path(human))

    def write_behavior(self, human: str, xml: str) -> None:
        atomic_write_text(self.behavior_path(human), xml)

    def behaviors(self) -> dict[str, str]:
        """human name -> tree XML, for every behaviors/*.xml present."""
        if not self.behaviors_dir.is_dir():
            return {}
        found = sorted(p.stem for p in self.behaviors_dir.glob("human*.xml"))
        return {name: read_text_limited(self.behavior_path(name)) for name in found}

    def has(self, name: str) -> bool:
        return (self.root / name).exists()
