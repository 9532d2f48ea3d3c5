"""The export targets as a registry: one class per simulator flavour, one module each (socrates.py,
hunav2.py, hunav1.py), all with the same interface. `export`, `bt check --target`, `bt library` and
generate's --target read the names from `bt.library.TARGETS`; `get_target` gives the class."""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import ClassVar

from socnavgen.bt.library import TARGETS, Target
from socnavgen.errors import ValidationFailed
from socnavgen.export.models import ExportedFile, ExportScene


class ExportTarget(ABC):
    """One simulator flavour: what it loads and how our run becomes those files."""

    name: ClassVar[Target]
    summary: ClassVar[str]  # one line for --help and the README
    btcpp: ClassVar[str]  # BehaviorTree.CPP version its trees are loaded with
    first_agent_id: ClassVar[int]  # id of human1 in its agents yaml

    @abstractmethod
    def build(self, scene: ExportScene, *, base: str, simulator: str) -> list[ExportedFile]:
        """All files, in memory; raises ValidationFailed (listing every problem) before anything is written."""


REGISTRY: dict[str, type[ExportTarget]] = {}


def register(cls: type[ExportTarget]) -> type[ExportTarget]:
    if cls.name not in TARGETS:
        raise ValueError(f"export target {cls.name!r} is not in bt.library.TARGETS")
    REGISTRY[cls.name] = cls
    return cls


def get_target(name: str) -> ExportTarget:
    _load_all()
    if name not in REGISTRY:
        raise ValidationFailed(f"unknown export format {name!r}", hint="one of: " + ", ".join(TARGETS))
    return REGISTRY[name]()


def _load_all() -> None:
    """Import every target module once (each registers its class)."""
    from socnavgen.export import hunav1, hunav2, socrates  # noqa: F401


def summaries() -> dict[str, str]:
    _load_all()
    return {name: REGISTRY[name].summary for name in TARGETS}
