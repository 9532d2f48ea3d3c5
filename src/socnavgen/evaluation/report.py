"""Aggregates evaluation outcomes into the paper's tables (plus what it could not measure) and
writes results.csv, results.md and the Table I rating sheet."""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from datetime import UTC, datetime
from pathlib import Path

from pydantic import BaseModel

from socnavgen.evaluation.outcome import RunOutcome
from socnavgen.evaluation.suite import EvalSuite
from socnavgen.run import RunFolder
from socnavgen.safeio import atomic_write_text


class Table3Row(BaseModel):
    method: str
    runs: int
    path_validity: float
    bt_validity: float
    path_first_attempt: float
    bt_first_attempt: float
    attempts_per_valid: float | None
    tokens_per_valid: float | None
    seconds_per_scenario: float
    verified_share: float | None
    paper_path_validity: float | None = None
    paper_bt_validity: float | None = None


class Table1Row(BaseModel):
    scene: str
    rough: bool
    proposals: int
    passed_checks: float
    first_attempt: float


def _share(flags: Sequence[bool]) -> float:
    return round(sum(flags) / len(flags), 2) if flags else 0.0


def table3(outcomes: list[RunOutcome], suite: EvalSuite) -> list[Table3Row]:
    rows = []
    for method in ("naive", "ours"):
        runs = [o for o in outcomes if o.table == "III" and o.method == method]
        if not runs:
            continue
        valid = [o for o in runs if o.valid]
        verified = [o.verified for o in valid if o.verified is not None]
        paper = suite.paper_table3.get(method)
        rows.append(Table3Row(
            method=method, runs=len(runs),
            path_validity=_share([o.path_valid for o in runs]), bt_validity=_share([o.bt_valid for o in runs]),
            path_first_attempt=_share([o.path_first for o in runs]), bt_first_attempt=_share([o.bt_first for o in runs]),
            attempts_per_valid=round(sum(o.attempts for o in runs) / len(valid), 1) if valid else None,
            tokens_per_valid=round(sum(o.tokens for o in runs) / len(valid)) if valid else None,
            seconds_per_scenario=round(sum(o.seconds for o in runs) / len(runs), 1),
            verified_share=round(sum(verified) / len(valid), 2) if valid and verified else None,
            paper_path_validity=paper.path_validity if paper else None,
            paper_bt_validity=paper.bt_validity if paper else None))
    return rows


def table1(outcomes: list[RunOutcome]) -> list[Table1Row]:
    rows = []
    keys = sorted({(o.scene, o.rough) for o in outcomes if o.table == "I"})
    for scene, rough in keys:
        runs = [o for o in outcomes if o.table == "I" and o.scene == scene and o.rough == rough]
        rows.append(Table1Row(scene=scene, rough=rough, proposals=len(runs),
                              passed_checks=_share([o.scenario_valid for o in runs]),
                              first_attempt=_share([o.scenario_first for o in runs])))
    return rows


def _fmt(value: object) -> str:
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    return f"{value:.2f}" if isinstance(value, float) else str(value)


def markdown_table(rows: Sequence[BaseModel]) -> str:
    if not rows:
        return "_no runs_\n"
    fields = list(type(rows[0]).model_fields)
    lines = ["| " + " | ".join(fields) + " |", "|" + "---|" * len(fields)]
    lines += ["| " + " | ".join(_fmt(getattr(r, f)) for f in fields) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def results_csv(outcomes: list[RunOutcome]) -> str:
    buf = io.StringIO()
    fields = list(RunOutcome.model_fields)
    writer = csv.DictWriter(buf, fieldnames=fields)
    writer.writeheader()
    for o in outcomes:
        writer.writerow(o.model_dump())
    return buf.getvalue()


def results_markdown(outcomes: list[RunOutcome], suite: EvalSuite, settings: dict, model: str | None) -> str:
    when = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    parts = [f"# socnavgen evaluation ({when})\n",
             f"- model: `{settings.get('llm')}`" + (f" ({model})" if model else ""),
             "- settings: " + ", ".join(f"{k}={v}" for k, v in settings.items() if k not in ("llm", "out")), "",
             "## Table III: path and behavior-tree validity (paper: GPT-4o, 5 runs x 3 scenes)\n",
             "Validity = the run's paths / trees passed every check within the attempt budget "
             f"({settings.get('max_requeries')} re-queries x {settings.get('max_restarts')} restarts). "
             "`paper_*` columns are the paper's numbers, measured with a different model.\n",
             markdown_table(table3(outcomes, suite))]
    if any(o.table == "I" for o in outcomes):
        parts += ["## Table I: scenario proposals passing the stage-1 checks\n",
                  "Realism and relevance need a human: fill in `ratings.md`.\n", markdown_table(table1(outcomes))]
    return "\n".join(parts)


def rating_sheet(outcomes: list[RunOutcome]) -> str:
    """One section per Table I proposal, with columns for a human rater to fill in."""
    lines = ["# Table I rating sheet", "",
             "Rate each proposal: realistic? executable in the simulator? relevant to the context and task? "
             "Write y/n in the last three columns.", "",
             "| scene | rough | # | passed checks | description | realistic | executable | relevant |",
             "|---|---|---|---|---|---|---|---|"]
    for o in outcomes:
        if o.table != "I":
            continue
        folder = RunFolder(Path(o.folder))
        text = "(no valid proposal)"
        if folder.scenario_path.is_file():
            s = folder.read_scenario()
            behaviors = "; ".join(f"{k}: {v}" for k, v in s.human_behaviors.items())
            text = f"{s.scenario_description} — Humans: {behaviors} — Robot: {s.expected_robot_behavior}"
        text = text.replace("|", "/").replace("\n", " ")
        lines.append(f"| {o.scene} | {_fmt(o.rough)} | {o.index} | {_fmt(o.scenario_valid)} | {text} |  |  |  |")
    return "\n".join(lines) + "\n"


def write_reports(out: Path, outcomes: list[RunOutcome], suite: EvalSuite, settings: dict,
                  model: str | None) -> list[Path]:
    files = {"results.csv": results_csv(outcomes),
             "results.md": results_markdown(outcomes, suite, settings, model)}
    if any(o.table == "I" for o in outcomes):
        files["ratings.md"] = rating_sheet(outcomes)
    for name, text in files.items():
        atomic_write_text(out / name, text)
    return [out / name for name in files]
