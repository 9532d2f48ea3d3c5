"""What one evaluated run achieved, read back from its run folder (manifest.json, transcript.jsonl),
so an interrupted evaluation resumes from the folders already written."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel

from socnavgen.llm.transcript import read_transcript
from socnavgen.run import Manifest, RunFolder

Method = Literal["ours", "naive"]


class RunOutcome(BaseModel):
    table: Literal["I", "III"]
    scene: str
    method: Method | Literal["proposal"]
    rough: bool
    index: int
    folder: str
    finished: bool  # the run ended (valid or failed): no need to run it again
    scenario_valid: bool = False
    path_valid: bool = False
    bt_valid: bool = False
    scenario_first: bool = False
    path_first: bool = False
    bt_first: bool = False
    attempts: int = 0
    tokens: int = 0
    seconds: float = 0.0
    verified: bool | None = None
    error: str | None = None

    @property
    def valid(self) -> bool:
        return self.path_valid and self.bt_valid


def _first_try(manifest: Manifest, stage: str) -> bool:
    """Valid on the very first reply: one attempt, no restart, for the stage and each of its keys."""
    keyed = [r for name, r in manifest.stages.items() if name.startswith(stage + ":")]
    records = keyed or [r for name, r in manifest.stages.items() if name == stage]  # the total sums the keys
    return bool(records) and all(r.status == "done" and r.attempts == 1 and r.restarts == 0 for r in records)


def _done(manifest: Manifest, stage: str) -> bool:
    record = manifest.stages.get(stage)
    return record is not None and record.status == "done"


def _naive_parts_ever_valid(folder: Path) -> tuple[bool, bool, bool, bool]:
    """For the naive baseline, which re-queries one combined reply, score paths and trees apart:
    (paths valid in some attempt, trees valid in some attempt, paths valid at first, trees valid at first)."""
    from socnavgen.proposal.naive import naive_parts
    from socnavgen.proposal.replies import NaiveReply

    run = RunFolder(folder)
    if not run.transcript_path.is_file():
        return False, False, False, False
    location = run.location()
    path_ok = tree_ok = False
    firsts: list[tuple[bool, bool]] = []
    for entry in read_transcript(run.transcript_path):
        if entry.get("stage") != "naive":
            continue
        if entry.get("value") is None:
            firsts.append((False, False))
            continue
        try:
            parts = naive_parts(NaiveReply.model_validate(entry["value"]), location)
        except Exception:  # a reply that parsed as JSON but not as the model: invalid attempt
            firsts.append((False, False))
            continue
        p, t = not parts["paths"], not parts["trees"]
        firsts.append((p, t))
        path_ok, tree_ok = path_ok or p, tree_ok or t
    first = firsts[0] if firsts else (False, False)
    return path_ok, tree_ok, first[0], first[1]


def read_outcome(folder: Path, *, table: Literal["I", "III"], scene: str, method: str, rough: bool,
                 index: int) -> RunOutcome:
    run = RunFolder(folder)
    base: dict[str, Any] = dict(table=table, scene=scene, method=method, rough=rough, index=index, folder=str(folder))
    if not run.manifest_path.is_file():
        return RunOutcome(**base, finished=False)
    manifest = run.read_manifest()
    records = [r for name, r in manifest.stages.items() if ":" not in name]
    tokens = sum(r.prompt_tokens + r.completion_tokens for r in records)
    outcome = RunOutcome(**base, finished=manifest.status in ("done", "failed"),
                         attempts=sum(r.attempts for r in records), tokens=tokens,
                         seconds=round(sum(r.seconds for r in records), 2), error=manifest.message)
    if method == "naive":
        outcome.scenario_valid = outcome.path_valid = outcome.bt_valid = _done(manifest, "naive")
        if not outcome.path_valid or not outcome.bt_valid:
            outcome.path_valid, outcome.bt_valid, outcome.path_first, outcome.bt_first = \
                _naive_parts_ever_valid(Path(folder))
        else:
            outcome.path_first = outcome.bt_first = _first_try(manifest, "naive")
    else:
        outcome.scenario_valid = _done(manifest, "scenario")
        outcome.scenario_first = _first_try(manifest, "scenario")
        outcome.path_valid = _done(manifest, "paths")
        outcome.path_first = _first_try(manifest, "paths")
        outcome.bt_valid = _done(manifest, "behaviors")
        outcome.bt_first = _first_try(manifest, "behaviors")
    verify = run.sim_dir / "verify.json"
    if verify.is_file():
        import json

        outcome.verified = bool(json.loads(verify.read_text()).get("passed"))
    return outcome
