"""`verify_run`: load a run, simulate it if it has no trace yet, derive the expectations, judge them, write
RUN/sim/verify.json. The public API used by `socnavgen verify` and `generate --verify`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from socnavgen.errors import InputFileError
from socnavgen.run.folder import RunFolder
from socnavgen.safeio import atomic_write_text
from socnavgen.sim.trace import Trace
from socnavgen.verify.evaluate import evaluate
from socnavgen.verify.expectations import derive_expectations
from socnavgen.verify.models import VerifyReport, VerifySettings

TRACE_FILE = "trace.npz"
REPORT_FILE = "verify.json"


def card_criteria_for(run: RunFolder) -> list[dict] | None:
    """The scenario card's success criteria, when the run came from a card."""
    if not run.request_path.is_file() or not run.read_request().card:
        return None
    from socnavgen.cards.library import card_criteria

    return card_criteria(run.root)


def simulate_missing(run_dir: Path, *, robot: str = "waypoints", location: Any = None, **config: Any) -> Trace:
    """Run the headless simulator on the run (saving RUN/sim/trace.npz) and return the trace."""
    from socnavgen.sim.scenario import simulate_run

    return simulate_run(Path(run_dir), robot, location, **config)


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
    loc = run.location(location)
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
    loaded = run.location(location)  # once: the simulation and the checks share the object
    options = dict(simulate_options or {})
    options.setdefault("location", loaded)
    trace = load_trace(run, simulate_if_missing=simulate_if_missing, simulate_options=options)
    report = verify_trace(run.root, trace, location=loaded, settings=settings)
    if write:
        atomic_write_text(run.sim_dir / REPORT_FILE, report.model_dump_json(indent=2) + "\n")
    return report
