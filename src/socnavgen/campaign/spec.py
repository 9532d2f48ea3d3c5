"""The campaign file (YAML): which scenarios, which robot policies, which seeds, which simulation settings
and which metrics. Validated with one clear error naming the line of the offending entry."""

from __future__ import annotations

import itertools
import re
import types
import typing
from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    Tag,
    ValidationError,
    field_validator,
    model_validator,
)

from socnavgen.errors import InputFileError
from socnavgen.limits import MAX_SIM_STEPS
from socnavgen.safeio import parse_yaml_text, read_text_limited
from socnavgen.text import did_you_mean

MAX_SEEDS = 100_000
MAX_SEED = 2**63 - 1  # the table's seed column is a 64-bit integer


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
            guesses = [f"{c}: {did_you_mean(c, known, cutoff=0.5) or 'no card is close'}" for c in unknown]
            raise ValueError(f"unknown card(s) {', '.join(unknown)} ({'; '.join(guesses)}); "
                             "`socnavgen cards list` shows every card")
        return value


SOURCE_KINDS = {"runs": "RunsSource", "folder": "FolderSource", "cards": "CardsSource"}


def _source_kind(value: Any) -> str | None:
    """Which kind of scenario entry this is, by the key it has (so a typo in its other keys is reported
    against that kind, not against whichever kind pydantic tried last)."""
    if isinstance(value, BaseModel):
        return type(value).__name__
    if isinstance(value, dict):
        return next((kind for key, kind in SOURCE_KINDS.items() if key in value), None)
    return None


ScenarioSource = Annotated[
    Annotated[RunsSource, Tag("RunsSource")] | Annotated[FolderSource, Tag("FolderSource")]
    | Annotated[CardsSource, Tag("CardsSource")],
    Discriminator(_source_kind, custom_error_type="scenario_kind",
                  custom_error_message="a scenario entry needs one of cards: (with locations:), runs: or folder:"),
]


ParamValue = float | int | bool | str
MAX_PARAMS = 32  # keys of one policy's params
MAX_SWEEP = 64  # policies one sweep expands into


class PolicySpec(BaseModel):
    """A robot policy: a built-in name (waypoints, sfm, ...), `module:Class` or `file.py:Class`, with its
    parameters (`params: {max_speed: 0.4, kinematics: holonomic}`: sim.robot.api.robot_from). A `sweep:
    {max_speed: [0.4, 0.6]}` entry expands into one policy per combination, named `NAME-KEY-VALUE...`."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field(pattern=r"^[A-Za-z0-9_.+-]{1,64}$")
    robot: str = Field(min_length=1, max_length=500)
    params: dict[str, ParamValue] = Field(default_factory=dict)

    @field_validator("params")
    @classmethod
    def _few_params(cls, value: dict[str, ParamValue]) -> dict[str, ParamValue]:
        if len(value) > MAX_PARAMS:
            raise ValueError(f"at most {MAX_PARAMS} params")
        bad = [k for k in value if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", k)]
        if bad:
            raise ValueError(f"param name {bad[0][:64]!r}: letters, digits and _ only")
        long = [k for k, v in value.items() if isinstance(v, str) and len(v) > 200]
        if long:
            raise ValueError(f"param {long[0]}: a text of at most 200 characters")
        return value


def _expand_sweep(entry: dict[str, Any]) -> list[dict[str, Any]]:
    """A policy entry with `sweep:` -> one entry per combination of the swept values (params win over none)."""
    sweep = entry.get("sweep")
    if sweep is None:
        return [entry]
    if not isinstance(sweep, dict) or not sweep or not all(isinstance(v, list) and v for v in sweep.values()):
        raise ValueError("sweep: a mapping of parameter name to a non-empty list of values")
    combos = list(itertools.product(*sweep.values()))
    if len(combos) > MAX_SWEEP:
        raise ValueError(f"a sweep of {len(combos)} combinations; at most {MAX_SWEEP}")
    base = {k: v for k, v in entry.items() if k != "sweep"}
    name = str(base.get("name") or _short_name(str(base.get("robot", ""))))
    out = []
    for combo in combos:
        params = {**(base.get("params") or {}), **dict(zip(sweep, combo, strict=True))}
        tag = "-".join(f"{k}-{v}" for k, v in zip(sweep, combo, strict=True))
        out.append({**base, "name": re.sub(r"[^A-Za-z0-9_.+-]", "_", f"{name}-{tag}")[:64], "params": params})
    return out


class SimulationSettings(BaseModel):
    model_config = ConfigDict(extra="forbid")
    dt: float = Field(0.05, gt=0.0, le=0.5)
    timeout: Annotated[float, Field(gt=0.0, le=3600.0)] | Literal["route"] = Field(
        "route", description="simulated seconds per episode, or `route` (the default): the limit `socnavgen "
        "simulate` gives the default robot on each scenario (twice its route at cruise speed plus its script's "
        "waits plus 30 s, at least 120 s; sim/engine/budget.py), the same for every policy")
    throttle: bool = True
    wall_timeout: float = Field(30.0, gt=0.0, le=3600.0,
                                description="wall-clock seconds an episode may take before it counts as failed")
    vary_people: bool = Field(True, description="draw each person's walking speed (and, once the simulator takes "
                              "them, personal space and start delay) from the seed: campaign/variation.py")

    @model_validator(mode="after")
    def _step_cap(self) -> SimulationSettings:
        """The same cap on steps as `socnavgen simulate` (dt 0.0001 x 3600 s would be 36 million steps)."""
        if self.timeout == "route":
            return self  # budget.time_limit keeps to the cap itself
        steps = self.timeout / self.dt
        if steps > MAX_SIM_STEPS:
            raise ValueError(f"timeout {self.timeout:g} s at dt {self.dt:g} s is {steps:,.0f} steps an episode, more "
                             f"than the {MAX_SIM_STEPS:,} allowed; raise dt or lower timeout")
        return self


class CampaignSpec(BaseModel):
    model_config = ConfigDict(extra="forbid")
    name: str = Field("campaign", pattern=r"^[A-Za-z0-9_.+-]{1,64}$")
    scenarios: list[ScenarioSource] = Field(min_length=1)
    policies: list[PolicySpec] = Field(min_length=1)
    seeds: list[int] = Field(default_factory=lambda: [0])
    simulation: SimulationSettings = Field(default_factory=SimulationSettings)
    metrics: list[str] | None = Field(None, description="metric columns to keep (default: all)")
    verify: bool = True
    trajectories: float = Field(10.0, ge=0.0, le=50.0, description="keep each episode's trajectories at this "
                                "many samples per second in OUT/trajectories/ (0: none)")
    base_dir: Path = Field(default=Path("."), exclude=True)

    @field_validator("policies", mode="before")
    @classmethod
    def _policy_shorthand(cls, value: Any) -> Any:
        """`- sfm` is short for `- {name: sfm, robot: sfm}`; an entry with `sweep:` is several policies."""
        if isinstance(value, list):
            entries = [{"name": _short_name(p), "robot": p} if isinstance(p, str) else p for p in value]
            return [e for entry in entries for e in (_expand_sweep(entry) if isinstance(entry, dict) else [entry])]
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
        if not 1 <= len(value) <= MAX_SEEDS:
            raise ValueError(f"give between 1 and {MAX_SEEDS} seeds (a number such as `seeds: 10`, or a list)")
        bad = [k for k in value if not 0 <= k <= MAX_SEED]
        if bad:
            raise ValueError(f"seed {bad[0]} is out of range: a seed is a whole number from 0 to 2**63 - 1")
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
    """The 1-based line of pydantic's error location in the YAML: of the deepest key found (not of its value:
    a block list starts on the line after its key), or of the list item."""
    line = node.start_mark.line + 1 if node is not None else None
    for key in loc:
        mark = None
        if isinstance(node, yaml.MappingNode):
            pair = next(((k, v) for k, v in node.value if getattr(k, "value", None) == key), None)
            if pair is not None:
                mark, node = pair[0].start_mark, pair[1]
        elif isinstance(node, yaml.SequenceNode) and isinstance(key, int) and key < len(node.value):
            node = node.value[key]
            mark = node.start_mark
        if mark is not None:  # union branch names etc. are not YAML keys: stay on the deepest real node
            line = mark.line + 1
    return line


def parse_campaign(text: str, file: Path | str = "<campaign>", base_dir: Path | None = None) -> CampaignSpec:
    data = parse_yaml_text(text, file)
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except RecursionError as exc:
        raise InputFileError("refused: YAML nested too deeply", file=file) from exc
    if not isinstance(data, dict):
        raise InputFileError("a campaign file is a YAML mapping with scenarios:, policies:, seeds:", file=file,
                             line=1, hint="see docs/campaign.md for an example")
    try:
        spec = CampaignSpec.model_validate(data)
    except ValidationError as exc:
        raise _campaign_error(exc.errors(), file, root) from exc
    spec.base_dir = Path(base_dir) if base_dir is not None else Path(".")
    for policy in spec.policies:  # `file.py:Class` is relative to the campaign file, like every other path
        module, _, cls = policy.robot.rpartition(":")
        if module.endswith(".py") and not Path(module).is_absolute():
            policy.robot = f"{spec.resolve(module).resolve()}:{cls}"
    return spec


GENERAL_HINT = ("a campaign needs scenarios: (cards: + locations:, runs: or folder:), policies: and seeds:; "
                "`socnavgen campaign example` prints a commented one")


def _campaign_error(errors: list[Any], file: Path | str, root: yaml.Node | None) -> InputFileError:
    """One message for pydantic's errors: an unknown key first (a typo, with the key it resembles), else the
    first error; named by its dotted place and the line of that place in the YAML."""
    extra = [e for e in errors if e["type"] == "extra_forbidden"]
    best = extra[0] if extra else errors[0]
    loc = tuple(k for k in best["loc"] if k not in SOURCE_KINDS.values())
    where = ".".join(str(k) for k in loc) or "(top level)"
    line = _line_of(root, loc)
    if best["type"] == "extra_forbidden":
        model = _model_at(best["loc"][:-1])
        known = list(model.model_fields) if model else []
        known = [k for k in known if k != "base_dir"]
        hint = did_you_mean(str(loc[-1]), known) or (f"the keys here are {', '.join(known)}" if known else None)
        return InputFileError(f"{where}: unknown key {str(loc[-1])!r}", file=file, line=line,
                              hint=hint or GENERAL_HINT)
    if best["type"] == "scenario_kind" and isinstance(best.get("input"), dict) and best["input"]:
        key = str(next(iter(best["input"])))  # an entry of no known kind: most likely a typo of its kind's key
        return InputFileError(f"{where}: unknown key {key!r}", file=file, line=_line_of(root, (*loc, key)),
                              hint=did_you_mean(key, SOURCE_KINDS) or best["msg"])
    message = best["msg"].removeprefix("Value error, ")
    return InputFileError(f"{where}: {message}", file=file, line=line, hint=GENERAL_HINT)


def _model_at(loc: tuple[Any, ...]) -> type[BaseModel] | None:
    """The pydantic model that validates the mapping at `loc` (to list the keys it takes)."""
    model: type[BaseModel] | None = CampaignSpec
    kinds: dict[str, type[BaseModel]] = {"RunsSource": RunsSource, "FolderSource": FolderSource, "CardsSource": CardsSource}
    for key in loc:
        if key in kinds:
            model = kinds[key]
        elif isinstance(key, str) and model is not None:
            field = model.model_fields.get(key)
            model = _first_model(field.annotation) if field else None
    return model


def _first_model(annotation: Any) -> type[BaseModel] | None:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    if isinstance(annotation, types.UnionType) or typing.get_origin(annotation) is not None:
        for arg in typing.get_args(annotation):
            found = _first_model(arg)
            if found is not None:
                return found
    return None


def load_campaign(path: Path | str) -> CampaignSpec:
    path = Path(path)
    return parse_campaign(read_text_limited(path, 1024 * 1024), file=path, base_dir=path.parent)
