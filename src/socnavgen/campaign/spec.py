"""The campaign file (YAML): which scenarios, which robot policies, which seeds, which simulation settings
and which metrics. Validated with one clear error naming the line of the offending entry."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from socnavgen.errors import InputFileError
from socnavgen.safeio import read_text_limited

MAX_SEEDS = 100_000


class RunsSource(BaseModel):
    """Explicit run folders (each holds paths.json and behaviors/)."""

    model_config = ConfigDict(extra="forbid")
    runs: list[str] = Field(min_length=1)


class FolderSource(BaseModel):
    """Every run folder directly inside `folder` (e.g. what `socnavgen eval` or a generate loop wrote)."""

    model_config = ConfigDict(extra="forbid")
    folder: str


class CardsSource(BaseModel):
    """Scenario cards instantiated on locations without an LLM; cards that do not fit a location are
    skipped (and listed). `cards: all` takes every card."""

    model_config = ConfigDict(extra="forbid")
    cards: list[str] | Literal["all"]
    locations: list[str] = Field(min_length=1)

    @field_validator("cards")
    @classmethod
    def _known_cards(cls, value: list[str] | str) -> list[str] | str:
        if value == "all":
            return value
        from socnavgen.cards.library import card_names

        known = card_names()
        unknown = [c for c in value if c not in known]
        if unknown:
            raise ValueError(f"unknown card(s) {', '.join(unknown)}; known: {', '.join(known)}")
        return value


ScenarioSource = RunsSource | FolderSource | CardsSource


class PolicySpec(BaseModel):
    """A robot policy: a built-in name (waypoints, sfm, ...), `module:Class` or `file.py:Class`."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field(pattern=r"^[A-Za-z0-9_.+-]{1,64}$")
    robot: str = Field(min_length=1, max_length=500)


class SimulationSettings(BaseModel):
    model_config = ConfigDict(extra="forbid")
    dt: float = Field(0.05, gt=0.0, le=0.5)
    timeout: float = Field(60.0, gt=0.0, le=3600.0, description="simulated seconds per episode")
    throttle: bool = True
    wall_timeout: float = Field(30.0, gt=0.0, le=3600.0,
                                description="wall-clock seconds an episode may take before it counts as failed")


class CampaignSpec(BaseModel):
    model_config = ConfigDict(extra="forbid")
    name: str = Field("campaign", pattern=r"^[A-Za-z0-9_.+-]{1,64}$")
    scenarios: list[ScenarioSource] = Field(min_length=1)
    policies: list[PolicySpec] = Field(min_length=1)
    seeds: list[int] = Field(default_factory=lambda: [0])
    simulation: SimulationSettings = Field(default_factory=SimulationSettings)
    metrics: list[str] | None = Field(None, description="metric columns to keep (default: all)")
    verify: bool = True
    base_dir: Path = Field(default=Path("."), exclude=True)

    @field_validator("policies", mode="before")
    @classmethod
    def _policy_shorthand(cls, value: Any) -> Any:
        """`- sfm` is short for `- {name: sfm, robot: sfm}`."""
        if isinstance(value, list):
            return [{"name": _short_name(p), "robot": p} if isinstance(p, str) else p for p in value]
        return value

    @field_validator("seeds", mode="before")
    @classmethod
    def _seed_count(cls, value: Any) -> Any:
        """`seeds: 10` means seeds 0..9."""
        if isinstance(value, int) and not isinstance(value, bool):
            if not 1 <= value <= MAX_SEEDS:
                raise ValueError(f"a number of seeds between 1 and {MAX_SEEDS}")
            return list(range(value))
        return value

    @field_validator("policies")
    @classmethod
    def _unique_policies(cls, value: list[PolicySpec]) -> list[PolicySpec]:
        names = [p.name for p in value]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"policy names must be unique; repeated: {', '.join(dup)} (give each a `name:`)")
        return value

    @field_validator("seeds")
    @classmethod
    def _unique_seeds(cls, value: list[int]) -> list[int]:
        if len(set(value)) != len(value):
            raise ValueError("seeds must be unique")
        return value

    @field_validator("metrics")
    @classmethod
    def _known_metrics(cls, value: list[str] | None) -> list[str] | None:
        if value is not None:
            from socnavgen.campaign.columns import known_metric_names

            unknown = [m for m in value if m not in known_metric_names()]
            if unknown:
                raise ValueError(f"unknown metric(s) {', '.join(unknown)}; see `socnavgen campaign metrics`")
        return value

    def resolve(self, path: str) -> Path:
        """A path from the campaign file, relative to the file's folder."""
        p = Path(path).expanduser()
        return p if p.is_absolute() else (self.base_dir / p)


def _short_name(robot: str) -> str:
    tail = robot.rpartition(":")[2] if ":" in robot else robot
    return "".join(ch if ch.isalnum() or ch in "_.+-" else "_" for ch in tail)[:64] or "policy"


def _line_of(node: yaml.Node | None, loc: tuple[Any, ...]) -> int | None:
    """The 1-based line of the YAML node at pydantic's error location (deepest node found)."""
    line = node.start_mark.line + 1 if node is not None else None
    for key in loc:
        if isinstance(node, yaml.MappingNode):
            nxt = next((v for k, v in node.value if getattr(k, "value", None) == key), None)
        elif isinstance(node, yaml.SequenceNode) and isinstance(key, int) and key < len(node.value):
            nxt = node.value[key]
        else:
            nxt = None
        if nxt is None:
            continue  # union branch names etc. are not YAML keys: stay on the deepest real node
        node = nxt
        line = node.start_mark.line + 1
    return line


def parse_campaign(text: str, file: Path | str = "<campaign>", base_dir: Path | None = None) -> CampaignSpec:
    try:
        data = yaml.safe_load(text)
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        raise InputFileError(f"malformed YAML: {getattr(exc, 'problem', None) or exc}", file=file,
                             line=mark.line + 1 if mark else None, hint="fix the YAML syntax at that line") from exc
    if not isinstance(data, dict):
        raise InputFileError("a campaign file is a YAML mapping with scenarios:, policies:, seeds:", file=file,
                             line=1, hint="see docs/campaign.md for an example")
    try:
        spec = CampaignSpec.model_validate(data)
    except ValidationError as exc:
        errors = exc.errors()
        best = min(errors, key=lambda e: len([k for k in e["loc"] if not isinstance(k, str) or
                                              k not in ("RunsSource", "FolderSource", "CardsSource")]))
        if any(k in ("RunsSource", "FolderSource", "CardsSource") for k in best["loc"]):
            best = _scenario_error(errors)
        loc = tuple(k for k in best["loc"] if k not in ("RunsSource", "FolderSource", "CardsSource"))
        where = ".".join(str(k) for k in loc) or "(top level)"
        raise InputFileError(f"{where}: {best['msg']}", file=file, line=_line_of(root, loc),
                             hint="a campaign needs scenarios: (runs:, folder: or cards: + locations:), "
                                  "policies: and seeds:; see docs/campaign.md") from exc
    spec.base_dir = Path(base_dir) if base_dir is not None else Path(".")
    for policy in spec.policies:  # `file.py:Class` is relative to the campaign file, like every other path
        module, _, cls = policy.robot.rpartition(":")
        if module.endswith(".py") and not Path(module).is_absolute():
            policy.robot = f"{spec.resolve(module).resolve()}:{cls}"
    return spec


def _scenario_error(errors: list[dict]) -> dict:
    """For a scenario entry matching no source kind, the error of the kind it most resembles (by its keys)."""
    for kind in ("CardsSource", "FolderSource", "RunsSource"):
        mine = [e for e in errors if kind in e["loc"]]
        if mine and not any(e["type"] == "extra_forbidden" for e in mine):
            return mine[0]
    return next(e for e in errors if e["type"] == "extra_forbidden")


def load_campaign(path: Path | str) -> CampaignSpec:
    path = Path(path)
    return parse_campaign(read_text_limited(path, 1024 * 1024), file=path, base_dir=path.parent)
