"""Table III over recorded capable-model fixtures: each fixture (tests/fixtures/replay/*.yaml with a
`request:` beside its `stages:`) is replayed through the real pipeline, every stage checked as a live
run would be, then simulated and verified. The table says, per fixture, whether each stage was valid
(at the first answer) and whether the scenario was verified in simulation (with its robustness)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import BaseModel

from socnavgen.errors import LLMError, SocnavgenError, StageFailed
from socnavgen.run import RunFolder, ScenarioRequest
from socnavgen.safeio import load_yaml_file


class FixtureRow(BaseModel):
    fixture: str
    location: str
    humans: int
    scenario_valid: bool
    paths_valid: bool
    trees_valid: bool
    first_attempt: bool  # every stage valid at its first answer
    verified: bool | None  # None: not simulated (an earlier stage failed)
    verify_rounds: int = 0  # rounds of the recorded --verify loop (0: recorded without --verify)
    failing: list[str] = []  # names of the failing criteria
    min_robustness: float | None = None
    verified_first: bool | None = None  # the first answers verified (before any --verify re-ask); None: not run
    eyes: str = ""  # what a person saw in the GIF frames of the recorded run (the fixture's `eyes.seen`)
    eyes_match: bool | None = None  # did that person judge the run as its text says (`eyes.matches`)


def fixture_request(path: Path, root: Path | None = None) -> ScenarioRequest:
    """The request recorded with a fixture; a relative location is resolved against `root`."""
    data = load_yaml_file(path)
    raw = data.get("request") if isinstance(data, dict) else None
    if not isinstance(raw, dict):
        raise SocnavgenError("a fixture needs a top-level 'request:' (location, context, task, rough)", file=path)
    request = ScenarioRequest.model_validate({**raw, "llm": f"replay:{path}"})
    location = Path(request.location)
    if not location.is_absolute() and root is not None:
        request = request.model_copy(update={"location": str(root / location)})
    return request


def _first_answers_verified(request: ScenarioRequest, out: Path) -> bool | None:
    """Replay only the first answers of a recorded --verify loop (no re-ask) and verify them."""
    from socnavgen.llm import make_llm
    from socnavgen.proposal import generate
    from socnavgen.verify import verify_run

    llm = make_llm(request.llm, transcript=out / "transcript.jsonl", use_cache=False)
    try:
        generate(request, llm, out, verify=False)
    except (StageFailed, LLMError):  # a stage failed, or its recorded answers no longer pass its checks
        return None
    return verify_run(out).passed


def _eyes(data: dict) -> tuple[str, bool | None]:
    eyes = data.get("eyes")
    if not isinstance(eyes, dict):
        eyes = {}
    matches = eyes.get("matches")
    return str(eyes.get("seen") or ""), matches if isinstance(matches, bool) else None


def replay_fixture(path: Path, out: Path, root: Path | None = None, verify: bool = True,
                   first_answers: bool = False) -> FixtureRow:
    """Replay one fixture into `out` and judge it. A fixture recorded with `--verify` (`verify_loop:
    true`) is replayed through the same loop, so its re-asked answers are used as they were live; with
    `first_answers`, its first answers are also replayed alone (into out/first) and verified, for Table III's
    first-answer column."""
    from socnavgen.llm import make_llm
    from socnavgen.llm.transcript import read_transcript
    from socnavgen.proposal import generate

    request = fixture_request(path, root)
    data = load_yaml_file(path)
    loop = bool(data.get("verify_loop"))
    llm = make_llm(request.llm, transcript=out / "transcript.jsonl", use_cache=False)
    failed, report, ended = False, None, None
    try:
        report = generate(request, llm, out, verify=verify and loop).verify
    except StageFailed:
        failed = True
    except LLMError as exc:  # the pipeline asked for an answer the live run was never asked for (a stage check or
        if "no reply left" not in exc.message:  # the verifier's verdicts changed since): the recording ends here
            raise
        ended = f"the recorded --verify loop has no answer for this verdict ({exc.message.split(',')[0]})"
    manifest = RunFolder(out).read_manifest()

    checks = [e for e in read_transcript(RunFolder(out).transcript_path) if e.get("kind") == "check"]

    def ok(stage: str) -> bool:
        record = manifest.stages.get(stage)
        if ended and record is not None:  # re-asked when the recording ended: its earlier answer was valid
            return any(e.get("stage") == stage and e.get("valid") for e in checks)
        return record is not None and record.status == "done"

    row = FixtureRow(fixture=path.stem, location=Path(request.location).name,
                     humans=len(RunFolder(out).read_scenario().human_behaviors) if ok("scenario") else 0,
                     scenario_valid=ok("scenario"), paths_valid=ok("paths"), trees_valid=ok("behaviors"),
                     first_attempt=not failed and all(e.get("valid") for e in checks), verified=None,
                     verify_rounds=manifest.stages["verify"].attempts if "verify" in manifest.stages else 0)
    if verify and not failed and ok("paths") and ok("behaviors"):  # (a recording may end before a run exists)
        from socnavgen.verify import verify_run

        if ended and not _complete(RunFolder(out)):  # it ended while stage 1's new answer was being planned
            row.verified, row.failing = False, [ended]
        else:
            report = report or verify_run(out)
            robustness = [f.robustness for f in report.findings if f.robustness is not None]
            row.verified = report.passed and ended is None
            row.failing = [f.name for f in report.failures] + ([ended] if ended else [])
            row.min_robustness = round(min(robustness), 2) if robustness else None
        row.verified_first = _first_answers_verified(request, out.with_name(out.name + ".first")) \
            if loop and first_answers else \
            row.verified
    row.eyes, row.eyes_match = _eyes(data)
    return row


def _complete(run: RunFolder) -> bool:
    """The run has paths and a tree for everybody (something to simulate)."""
    return run.paths_path.is_file() and set(run.read_scenario().human_behaviors) <= set(run.behaviors())


def fixture_paths(folder: Path) -> list[Path]:
    """Fixtures with a recorded request (scripts without one are unit-test scripts, not fixtures)."""
    found = []
    for path in sorted(Path(folder).glob("*.yaml")):
        data = load_yaml_file(path)
        if isinstance(data, dict) and isinstance(data.get("request"), dict):
            found.append(path)
    return found


def fixtures_markdown(rows: list[FixtureRow]) -> str:
    """Table III over fixtures: validity per stage at the first answer, verified at the first answers and at
    the end of the recorded --verify loop, and whether a person who looked at the frames agrees."""
    head = ("| fixture | location | humans | scenario + spec valid | paths valid | trees valid | every answer valid "
            "at 1st try | verified, first answers | verified, end of --verify | --verify rounds | lowest robustness "
            "| eyes: as its text says | failing criteria |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    lines = [head]
    for r in rows:
        lines.append(f"| {r.fixture} | {r.location} | {r.humans} | {_yes(r.scenario_valid)} | {_yes(r.paths_valid)} | "
                     f"{_yes(r.trees_valid)} | {_yes(r.first_attempt)} | {_verdict(r.verified_first)} | "
                     f"{_verdict(r.verified)} | {r.verify_rounds or '–'} | "
                     f"{'–' if r.min_robustness is None else f'{r.min_robustness:+.2f}'} | {_verdict(r.eyes_match)} | "
                     f"{'; '.join(r.failing) or '–'} |")
    first = [r.verified_first for r in rows if r.verified_first is not None]
    final = [r.verified for r in rows if r.verified is not None]
    judged = [r for r in rows if r.eyes_match is not None and r.verified is not None]
    disagree = sum(r.eyes_match != r.verified for r in judged)
    lines.append(f"| **all** | | | {sum(r.scenario_valid for r in rows)}/{len(rows)} | "
                 f"{sum(r.paths_valid for r in rows)}/{len(rows)} | {sum(r.trees_valid for r in rows)}/{len(rows)} | "
                 f"{sum(r.first_attempt for r in rows)}/{len(rows)} | {sum(first)}/{len(rows)} | "
                 f"{sum(final)}/{len(rows)} | | | {len(judged) - disagree}/{len(judged)} agree | |")
    return "\n".join(lines)


def _verdict(flag: bool | None) -> str:
    return "–" if flag is None else ("**yes**" if flag else "no")


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"


def record_fixture(run_dir: Path, out: Path, note: str = "") -> Path:
    """Turn a recorded run (request.json + transcript.jsonl) into a replay fixture: the request and every
    raw reply per stage and key, in the order they were served (invalid ones too, so a replay re-asks
    exactly as the live run did)."""
    import yaml

    from socnavgen.llm.transcript import read_transcript
    from socnavgen.safeio import atomic_write_text

    run = RunFolder(run_dir)
    request = run.read_request()
    stages: dict[str, Any] = {}  # stage -> [raw] or {key: [raw]}
    model = None
    for entry in read_transcript(run.transcript_path):
        raw, stage = entry.get("raw"), entry.get("stage")
        if not isinstance(raw, str) or not isinstance(stage, str):
            continue
        model = model or entry.get("model")
        key = entry.get("key")
        if key is None:
            stages.setdefault(stage, []).append(raw)
        else:
            stages.setdefault(stage, {}).setdefault(key, []).append(raw)
    fields = {k: v for k, v in request.model_dump(include={"location", "context", "task", "rough", "target"}).items()
              if v is not None}
    loop = "verify" in run.read_manifest().stages
    header = (f"# Replay fixture recorded from a live run ({model or 'unknown model'}); {note}\n"
              f"# Replay: socnavgen generate --llm replay:THIS ... or socnavgen eval --fixtures DIR\n")
    data = {"request": fields, **({"verify_loop": True} if loop else {}), "stages": stages}
    text = header + yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=120)
    atomic_write_text(out, text)
    return out
