"""`verify_run`: load a run, simulate it if it has no trace yet, derive the expectations, judge them, write
RUN/sim/verify.json. The public API used by `socnavgen verify` and `generate --verify`."""

from __future__ import annotations

import importlib
import inspect
from pathlib import Path
from typing import Any

from socnavgen.errors import InputFileError, StageFailed
from socnavgen.location import load_location
from socnavgen.run.folder import RunFolder
from socnavgen.safeio import atomic_write_text
from socnavgen.sim.trace import Trace
from socnavgen.verify.evaluate import evaluate
from socnavgen.verify.expectations import derive_expectations
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
    """The scenario card's success criteria, when the run came from a card and the cards module offers them."""
    if not run.request_path.is_file() or not run.read_request().card:
        return None
    try:
        library = importlib.import_module("socnavgen.cards.library")
    except ImportError:
        return None
    fn = getattr(library, "card_criteria", None)
    if fn is None:
        return None
    criteria = fn(run.root)
    return [dict(c) if not isinstance(c, dict) and hasattr(c, "items") else c for c in (criteria or [])]


def simulate_missing(run_dir: Path, *, robot: str = "waypoints", location: Any = None, **config: Any) -> Trace:
    """Run the headless simulator on the run with the default robot plugin, save RUN/sim/trace.npz and return
    the trace. Uses `simulate_run(run_dir, ...)` when the simulator offers one, else builds the simulation from
    the run folder (`socnavgen.sim.scenario.load_simulation`)."""
    run_dir = Path(run_dir)
    for module_name in ("socnavgen.sim.engine", "socnavgen.sim.scenario"):
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue
        fn = getattr(module, "simulate_run", None)
        if fn is not None:
            wanted = {"robot": robot, "location": location, **config}
            params = inspect.signature(fn).parameters
            if not any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values()):
                wanted = {k: v for k, v in wanted.items() if k in params}
            result = fn(run_dir, **{k: v for k, v in wanted.items() if v is not None})
            trace = result if isinstance(result, Trace) else getattr(result, "trace", None)
            if not isinstance(trace, Trace) and (run_dir / "sim" / TRACE_FILE).is_file():
                trace = Trace.load(run_dir / "sim" / TRACE_FILE)
            if not isinstance(trace, Trace):
                raise StageFailed("the simulator returned no trace", file=run_dir)
            if not (run_dir / "sim" / TRACE_FILE).is_file():
                trace.save(run_dir / "sim" / TRACE_FILE)
            return trace
    try:
        from socnavgen.sim.engine import SimConfig
        from socnavgen.sim.robot import load_policy
        from socnavgen.sim.scenario import load_simulation
    except ImportError as exc:
        raise StageFailed("the run has no sim/trace.npz and the simulator is not available", file=run_dir,
                          hint="run `socnavgen simulate RUN` first") from exc
    loc_dir = Path(location) if isinstance(location, str | Path) else None
    sim = load_simulation(run_dir, load_policy(robot), SimConfig(**config), location_dir=loc_dir)
    sim.meta["robot_plugin"] = robot
    trace = sim.run()
    trace.save(run_dir / "sim" / TRACE_FILE)
    return trace


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
    """Judge an in-memory trace against the run's expectations (nothing written)."""
    run = RunFolder(Path(run_dir))
    settings = settings or VerifySettings()
    plan = run.read_paths()
    loc = resolve_location(run, location)
    expectations = derive_expectations(plan, run.behaviors(), loc, card_criteria_for(run))
    findings = evaluate(expectations, trace, settings)
    seconds = float(trace.t[-1] - trace.t[0]) if trace.steps else 0.0
    return VerifyReport(run=str(run.root), passed=all(f.passed or not f.required for f in findings), findings=findings,
                        settings=settings, trace_steps=trace.steps, trace_seconds=round(seconds, 3),
                        end_reason=trace.end_reason)


def verify_run(run_dir: Path | str, *, simulate_if_missing: bool = True, location: Any = None,
               settings: VerifySettings | None = None, write: bool = True,
               simulate_options: dict | None = None, **thresholds: float) -> VerifyReport:
    """Verify a run folder: simulate if RUN/sim/trace.npz is missing (`simulate_options`: robot="waypoints",
    dt, timeout, seed), judge every expectation, write RUN/sim/verify.json. `thresholds` override
    VerifySettings fields (distance=2.5, near=3.0, passing=3.0, group_spread=3.0, group_fraction=0.8)."""
    run = RunFolder(Path(run_dir))
    if not run.paths_path.is_file():
        raise InputFileError("no paths.json in this run", file=run.root,
                             hint="verify needs a generated run (socnavgen generate ... --out RUN)")
    settings = (settings or VerifySettings()).model_copy(update={k: v for k, v in thresholds.items()
                                                                 if v is not None})
    options = dict(simulate_options or {})
    if location is not None and isinstance(location, str | Path):
        options.setdefault("location", location)
    trace = load_trace(run, simulate_if_missing=simulate_if_missing, simulate_options=options)
    report = verify_trace(run.root, trace, location=location, settings=settings)
    if write:
        atomic_write_text(run.sim_dir / REPORT_FILE, report.model_dump_json(indent=2) + "\n")
    return report
