"""A run folder read once: `LoadedRun` reads and validates each file of a run (request.json, paths.json,
spec.json, behaviors/*.xml) the first time a stage asks for it and keeps the result, so a campaign that
simulates and verifies the same scenario thousands of times reads it once per worker. The project's rule:
load the run once and pass the object on, not its path.

Reads go through RunFolder (contained paths, size limits, the same messages); a file that fails to load is
not kept, so asking again raises the very same error. Each part is read when first asked for, in the
order the caller asks: every error (file, line, hint) is the one reading the folder directly would give.
Run folders must not change while a LoadedRun of them is in use (a campaign's never do).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from socnavgen.run.folder import RunFolder
from socnavgen.run.models import PathPlan, ScenarioRequest
from socnavgen.run.spec import ScenarioSpec

if TYPE_CHECKING:
    from socnavgen.location import Location

T = TypeVar("T")


class LoadedRun:
    """The contents of one run folder, each part read and validated once. Treat what it returns as read
    only: the same objects are handed to every episode."""

    def __init__(self, root: Path | str | RunFolder) -> None:
        self.folder = root if isinstance(root, RunFolder) else RunFolder(Path(root))
        self._memo: dict[Any, Any] = {}
        self._by_location: dict[Any, tuple[Any, Any]] = {}

    def __repr__(self) -> str:
        return f"LoadedRun({str(self.folder.root)!r})"

    @property
    def root(self) -> Path:
        return self.folder.root

    def derived(self, key: Any, build: Callable[[], T]) -> T:
        """`build()` computed once for this run and kept under `key` (hashable): what a later stage derives
        from the run alone (the verifier's criteria, a card's criteria). Nothing is kept when it raises."""
        if key not in self._memo:  # build outside any handler: its errors carry no unrelated context
            self._memo[key] = build()
        return self._memo[key]

    def for_location(self, key: Any, location: Any, build: Callable[[], T]) -> T:
        """`derived` for values that also depend on a loaded Location (kept per Location object: the same
        folder loaded twice is two objects, and an object's id is never mistaken for another's)."""
        slot = (key, id(location))
        kept = self._by_location.get(slot)
        if kept is not None and kept[0] is location:
            return kept[1]
        value = build()
        self._by_location[slot] = (location, value)
        return value

    # -- the files -------------------------------------------------------------------------------
    def has_request(self) -> bool:
        return self.derived("has_request", self.folder.request_path.is_file)

    def request(self) -> ScenarioRequest:
        """request.json, its location resolved (RunFolder.read_request)."""
        return self.derived("request", self.folder.read_request)

    def paths(self) -> PathPlan:
        """paths.json (RunFolder.read_paths)."""
        return self.derived("paths", self.folder.read_paths)

    def spec(self) -> ScenarioSpec | None:
        """spec.json, or None for runs made before specs existed (RunFolder.read_spec)."""
        return self.derived("spec", self.folder.read_spec)

    def behaviors(self) -> dict[str, str]:
        """human name -> tree XML, for every behaviors/*.xml present (RunFolder.behaviors)."""
        return self.derived("behaviors", self.folder.behaviors)

    def behavior_path(self, human: str) -> Path:
        """behaviors/<human>.xml, resolved inside the run folder (RunFolder.behavior_path)."""
        return self.derived(("behavior_path", human), lambda: self.folder.behavior_path(human))

    def location(self, override: Location | Path | str | None = None) -> Location:
        """RunFolder.location: `override` passed through (a Location) or loaded (a folder); without one the
        location request.json names, loaded once."""
        if override is not None:
            return self.folder.location(override)
        return self.derived("location", self.folder.location)

    def plan_mistakes(self, location: Location, *, interaction_points: bool = True) -> list[str]:
        """run.checks.plan_mistakes of paths.json on `location`'s scene graph, checked once per location."""
        from socnavgen.run.checks import plan_mistakes

        return self.for_location(("plan_mistakes", interaction_points), location,
                                 lambda: plan_mistakes(self.paths(), location.scene_graph,
                                                       interaction_points=interaction_points))


def load_run(run: LoadedRun | RunFolder | Path | str) -> LoadedRun:
    """THE way to get a LoadedRun: one passed in is used as is (its reads are already done); a folder or a
    path gives a new one."""
    return run if isinstance(run, LoadedRun) else LoadedRun(run)
