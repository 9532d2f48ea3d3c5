"""`generate(request, llm, out)`: scenario -> paths -> behavior trees into a run folder.

Each stage writes its file atomically when it succeeds, and manifest.json after every attempt, so an
interrupted run resumes at the first missing file (re-running on the same folder) and a failed one
keeps everything it produced. `redo` deletes the files of the named stages (and of the stages that
depend on them) before resuming.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING

from socnavgen import __version__
from socnavgen.errors import LLMError, SocnavgenError, StageFailed
from socnavgen.llm.base import LLM
from socnavgen.location import load_location
from socnavgen.proposal.conversation import ProgressFn, Recorder, no_progress
from socnavgen.proposal.naive import generate_naive
from socnavgen.proposal.review import ReviewHook
from socnavgen.proposal.stages import Stages
from socnavgen.proposal.verify_loop import Verifier, verify_and_repair
from socnavgen.run import Manifest, PathPlan, RunFolder, ScenarioProposal, ScenarioRequest
from socnavgen.run.spec import ScenarioSpec

if TYPE_CHECKING:
    from socnavgen.verify.models import VerifyReport

STAGES = ("scenario", "paths", "behaviors")
# Fields that define WHAT was asked: a folder holding another request is not resumed silently.
IDENTITY_FIELDS = ("location", "context", "task", "rough", "card", "naive", "target")


@dataclass
class Run:
    folder: RunFolder
    scenario: ScenarioProposal
    paths: PathPlan
    behaviors: dict[str, str] = field(default_factory=dict)
    manifest: Manifest | None = None
    verify: VerifyReport | None = None  # the verifier's report when --verify ran
    spec: ScenarioSpec | None = None


def stages_to_redo(redo: set[str] | None) -> set[str]:
    """A stage's files depend on the stages before it: redoing one redoes all that follow."""
    if not redo:
        return set()
    unknown = set(redo) - set(STAGES)
    if unknown:
        raise SocnavgenError(f"cannot redo {', '.join(sorted(unknown))}", hint=f"stages are {', '.join(STAGES)}")
    first = min(STAGES.index(s) for s in redo)
    return set(STAGES[first:])


def copy_run(source: Path, out: Path) -> None:
    """`--from RUN --out OTHER`: start OTHER as a copy of RUN (its simulation results are left behind)."""
    source, out = Path(source), Path(out)
    if not (source / "request.json").is_file():
        raise SocnavgenError("not a run folder (no request.json)", file=source, hint="give the --out of an earlier run")
    if out.exists() and any(out.iterdir()):
        raise SocnavgenError("the --out folder already exists and is not empty", file=out,
                             hint="choose a new --out, or omit it to regenerate in place")
    shutil.copytree(source, out, ignore=shutil.ignore_patterns("sim", ".*.tmp"), dirs_exist_ok=True)


def _clear(run: RunFolder, stages: set[str], manifest: Manifest) -> None:
    if "scenario" in stages:
        run.scenario_path.unlink(missing_ok=True)
        run.proposals_path.unlink(missing_ok=True)
        run.spec_path.unlink(missing_ok=True)
    if "paths" in stages:
        run.paths_path.unlink(missing_ok=True)
        spec = run.read_spec() if run.spec_path.is_file() else None
        if spec is not None:  # its grounding belongs to the paths being redone
            for encounter in spec.encounters:
                encounter.node = None
            run.write_spec(spec)
    if "behaviors" in stages and run.behaviors_dir.is_dir():
        for xml in run.behaviors_dir.glob("*.xml"):
            xml.unlink()
    for name in list(manifest.stages):
        if name.split(":")[0] in stages or name == "verify":
            del manifest.stages[name]


def _identity(request: ScenarioRequest, field: str) -> object:
    """A request field as compared on resume: the location as the folder it names, however spelled."""
    value = getattr(request, field)
    return Path(value).resolve() if field == "location" else value


def _open_request(run: RunFolder, request: ScenarioRequest) -> None:
    if run.request_path.is_file():
        old = run.read_request()
        changed = [f for f in IDENTITY_FIELDS if _identity(old, f) != _identity(request, f)]
        if changed:
            raise SocnavgenError(f"this run folder holds a different request ({', '.join(changed)} differ)",
                                 file=run.request_path,
                                 hint="use a new --out, or --from RUN --redo STAGE to change a run")
    run.write_request(request)


def _open_manifest(run: RunFolder, request: ScenarioRequest, llm: LLM) -> Manifest:
    if run.manifest_path.is_file():
        manifest = run.read_manifest()
    else:
        manifest = Manifest(socnavgen_version=__version__, created=datetime.now(UTC).isoformat(timespec="seconds"),
                            llm=request.llm)
    manifest.llm, manifest.model, manifest.status, manifest.message = request.llm, getattr(llm, "model", None), \
        "running", None
    return manifest


def generate(request: ScenarioRequest, llm: LLM, out: Path, *, redo: set[str] | None = None,
             review: ReviewHook | None = None, progress: ProgressFn = no_progress, verify: bool = False,
             verifier: Verifier | None = None) -> Run:
    """Run (or resume) the pipeline into `out`. Raises StageFailed / LLMError with the run folder intact
    and manifest.json saying `failed`. With `verify`, a run whose verification still fails ends with
    manifest status `failed` (the files are kept; `Run.verify` holds the report)."""
    run = RunFolder(Path(out))
    run.root.mkdir(parents=True, exist_ok=True)
    location = load_location(request.location)
    _open_request(run, request)
    manifest = _open_manifest(run, request, llm)
    _clear(run, stages_to_redo(redo), manifest)
    recorder = Recorder(run, manifest, progress)
    recorder.save()
    stages = Stages(request, llm, run, location, recorder, review)
    spec = None
    try:
        if request.naive:
            scenario, paths, trees = generate_naive(stages)
        else:
            scenario, spec = stages.scenario()
            scenario, _, paths, spec = stages.plan(scenario, spec)
            trees = stages.behaviors(scenario, paths, spec)
        report = None
        if verify:
            scenario, spec, paths, trees, report = verify_and_repair(stages, scenario, spec, paths, trees,
                                                                     verifier or default_verifier())
    except (StageFailed, LLMError) as exc:
        _mark_failed(manifest, exc.message)
        recorder.save()
        raise
    except BaseException as exc:  # interrupted: the files written so far are complete; resume later
        _mark_failed(manifest, f"interrupted ({type(exc).__name__}: {exc})")
        recorder.save(interrupted=True)
        raise
    if report is not None and not report.passed:
        manifest.status = "failed"
        manifest.message = "verification failed: " + "; ".join(f"{f.name}: {f.evidence}" for f in report.failures)[:2000]
    else:
        manifest.status, manifest.message = "done", None
    recorder.save()
    return Run(folder=run, scenario=scenario, paths=paths, behaviors=trees, manifest=manifest, verify=report,
               spec=spec)


def _mark_failed(manifest: Manifest, message: str) -> None:
    manifest.status, manifest.message = "failed", message
    for record in manifest.stages.values():
        if record.status == "running":
            record.status = "failed"


def default_verifier() -> Verifier:
    """The verifier `--verify` calls (tests may pass their own to `generate`)."""
    from socnavgen.verify import verify_run

    return verify_run
