"""`verify_run`: load a run, simulate it if it has no trace yet, monitor its acceptance criteria (spec.json,
else derived from paths, trees and card) and its trees' key nodes, blame each failure, write
RUN/sim/verify.json. The public API used by `socnavgen verify`, `generate --verify` and campaigns."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from socnavgen.errors import InputFileError
from socnavgen.location import load_location
from socnavgen.run.folder import RunFolder
from socnavgen.safeio import atomic_write_text
from socnavgen.sim.trace import Trace
from socnavgen.verify.judge import judge
from socnavgen.verify.models import VerifyReport, VerifySettings

TRACE_FILE = "trace.npz"
REPORT_FILE = "verify.json"


def resolve_location(run: RunFolder, location: Any = None) -> Any:
    """The run's location: given, or request.json's `location` (as written, else relative to the run)."""
    if location is not None and not isinstance(location, str | Path):
        return location
    if location is None:
        if not run.request_path.is_file():
            raise InputFileError("no request.json: cannot tell which location this run uses", file=run.root,
                                 hint="pass --location, or verify a folder written by `socnavgen generate`")
        location = run.read_request().location
    candidates = [Path(location), run.root / location]
    for path in candidates:
        if (path / "location.yaml").is_file():
            return load_location(path)
    raise InputFileError(f"location folder {location!s} not found", file=run.request_path,
                         hint="the location path in request.json is relative to where generate ran")


def card_criteria_for(run: RunFolder) -> list[dict] | None:
    """The scenario card's success criteria, when the run came from a card."""
    if not run.request_path.is_file() or not run.read_request().card:
        return None
    from socnavgen.cards.library import card_criteria

    return card_criteria(run.root)


def simulate_missing(run_dir: Path, **options: Any) -> Trace:
    """Run the headless simulator on the run (saving RUN/sim/trace.npz) and return the trace. `options`:
    robot (the simulator's default policy when absent), location, dt, timeout, seed."""
    from socnavgen.sim.scenario import simulate_run

    return simulate_run(Path(run_dir), **options)


def load_trace(run: RunFolder, *, simulate_if_missing: bool, simulate_options: dict | None = None) -> Trace:
    path = run.sim_dir / TRACE_FILE
    if path.is_file():
        try:
            return Trace.load(path)
        except (OSError, ValueError, KeyError) as exc:
            raise InputFileError(f"cannot read the trace: {exc}", file=path,
                                 hint="re-run `socnavgen simulate RUN`") from exc
    if not simulate_if_missing:
        raise InputFileError("no simulation trace", file=path, hint="run `socnavgen simulate RUN` first")
    return simulate_missing(run.root, **(simulate_options or {}))


def verify_trace(run_dir: Path | str, trace: Trace, *, location: Any = None,
                 settings: VerifySettings | None = None) -> VerifyReport:
    """Judge an in-memory trace against the run's criteria (nothing written)."""
    run = RunFolder(Path(run_dir))
    loc = resolve_location(run, location)
    return judge(trace, plan=run.read_paths(), location=loc, spec=run.read_spec(), trees=run.behaviors(),
                 card_criteria=card_criteria_for(run), settings=settings or VerifySettings(), run_name=str(run.root))


def verify_run(run_dir: Path | str, *, simulate_if_missing: bool = True, location: Any = None,
               settings: VerifySettings | None = None, write: bool = True,
               simulate_options: dict | None = None, **thresholds: float | bool) -> VerifyReport:
    """Verify a run folder: simulate if RUN/sim/trace.npz is missing (`simulate_options`: robot, dt, timeout,
    seed), judge every criterion, write RUN/sim/verify.json. `thresholds` override VerifySettings fields
    (distance=2.0, near=1.0, passing=2.5, group_spread=2.5, deadlock_seconds=10, reaction_seconds=5,
    collisions_fail=True); unknown names are ignored."""
    run = RunFolder(Path(run_dir))
    if not run.paths_path.is_file():
        raise InputFileError("no paths.json in this run", file=run.root,
                             hint="verify needs a generated run (socnavgen generate ... --out RUN)")
    fields = VerifySettings.model_fields
    settings = (settings or VerifySettings()).model_copy(update={k: v for k, v in thresholds.items()
                                                                 if v is not None and k in fields})
    options = dict(simulate_options or {})
    if location is not None and isinstance(location, str | Path):
        options.setdefault("location", location)
    trace = load_trace(run, simulate_if_missing=simulate_if_missing, simulate_options=options)
    report = verify_trace(run.root, trace, location=location, settings=settings)
    if write:
        atomic_write_text(run.sim_dir / REPORT_FILE, report.model_dump_json(indent=2) + "\n")
    return report
