"""`verify_run`: load a run, simulate it if it has no trace yet, monitor its acceptance criteria (spec.json,
else derived from paths, trees and card) and its trees' key nodes, blame each failure, write
RUN/sim/verify.json. The public API used by `socnavgen verify`, `generate --verify` and campaigns."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from socnavgen.errors import InputFileError
from socnavgen.run.folder import RunFolder
from socnavgen.run.loaded import LoadedRun, load_run
from socnavgen.safeio import atomic_write_text
from socnavgen.sim.trace import Trace
from socnavgen.verify.judge import judge, prepare
from socnavgen.verify.models import VerifyReport, VerifySettings

TRACE_FILE = "trace.npz"
REPORT_FILE = "verify.json"


def card_criteria_for(run: RunFolder | LoadedRun) -> list[dict] | None:
    """The scenario card's success criteria, when the run came from a card (kept with a LoadedRun)."""
    loaded = load_run(run)

    def build() -> list[dict] | None:
        if not loaded.has_request() or not loaded.request().card:
            return None
        from socnavgen.cards.library import card_criteria

        return card_criteria(loaded.root)

    return loaded.derived("verify.card_criteria", build)


def simulate_missing(run_dir: Path | str | LoadedRun, **options: Any) -> Trace:
    """Run the headless simulator on the run (saving RUN/sim/trace.npz) and return the trace. `options`:
    robot (the simulator's default policy when absent), location, dt, timeout, seed."""
    from socnavgen.sim import simulate_run

    return simulate_run(run_dir if isinstance(run_dir, LoadedRun) else Path(run_dir), **options)


def load_trace(run: RunFolder | LoadedRun, *, simulate_if_missing: bool,
               simulate_options: dict | None = None) -> Trace:
    """RUN/sim/trace.npz when it is the run's current simulation (or has no record at all: a trace made by
    hand is judged as it is); otherwise (missing, half-written, or made from files that changed since:
    sim/outputs.stale_reason) simulated again with the robot and settings it was made with (`simulate_options`
    override them), or refused without `simulate_if_missing`."""
    from socnavgen.sim import recorded_options, stale_reason

    folder = run.folder if isinstance(run, LoadedRun) else run
    path = folder.sim_dir / TRACE_FILE
    options = dict(simulate_options or {})
    stale = None
    if path.is_file():
        stale = stale_reason(folder.root, options.get("location") or run.location())
        if stale is None:
            try:
                return Trace.load(path)
            except (OSError, ValueError, KeyError) as exc:
                raise InputFileError(f"cannot read the trace: {exc}", file=path,
                                     hint="re-run `socnavgen simulate RUN`") from exc
        options = {**recorded_options(folder.root), **options}
    if not simulate_if_missing:
        raise InputFileError(f"stale simulation: {stale}" if stale else "no simulation trace", file=path,
                             hint="run `socnavgen simulate RUN` again first" if stale else
                             "run `socnavgen simulate RUN` first")
    return simulate_missing(run if isinstance(run, LoadedRun) else run.root, **options)


def verify_trace(run_dir: Path | str | LoadedRun, trace: Trace, *, location: Any = None,
                 settings: VerifySettings | None = None) -> VerifyReport:
    """Judge an in-memory trace against the run's criteria (nothing written). `run_dir`: a LoadedRun (what
    the verifier derives from the run alone, criteria and tree checks, is kept with it: campaign workers keep
    one per scenario) or a run folder."""
    run = load_run(run_dir)
    loc = run.location(location)
    plan, spec, trees = run.paths(), run.spec(), run.behaviors()
    cards = card_criteria_for(run)
    settings = settings or VerifySettings()
    prepared = run.for_location(("verify.prepared", settings.model_dump_json()), loc,
                                lambda: prepare(plan, loc, spec, trees, cards, settings))
    return judge(trace, plan=plan, location=loc, spec=spec, trees=trees, card_criteria=cards, settings=settings,
                 run_name=str(run.root), prepared=prepared)


def blame_the_policy(report: VerifyReport, policy: str, seed: int) -> None:
    """Put every failure of `report` on the robot policy under test: the scenario verified with the default
    robot on this seed, so the policy is what differs (campaigns and `socnavgen verify` of a run simulated with
    another robot)."""
    from socnavgen.sim import DEFAULT_ROBOT

    for f in report.failures:
        f.blame, f.blame_human, f.stage = "policy", None, None
        f.blame_reason = (f"the scenario verified with the default robot ({DEFAULT_ROBOT}) on seed {seed}: "
                          f"the policy under test ({policy}) is what differs")


def _default_verifies(run: LoadedRun, location: Any, settings: VerifySettings, options: dict) -> bool:
    """Whether the run verifies when simulated with the default robot and the same settings (nothing saved)."""
    from socnavgen.sim import DEFAULT_ROBOT, simulate_run

    kept = {k: options[k] for k in ("dt", "timeout", "seed", "throttle") if k in options}
    trace = simulate_run(run, DEFAULT_ROBOT, location=location, save=False, plot=False, **kept)
    return verify_trace(run, trace, location=location, settings=settings).passed


def verify_run(run_dir: Path | str, *, simulate_if_missing: bool = True, location: Any = None,
               settings: VerifySettings | None = None, write: bool = True,
               simulate_options: dict | None = None, **thresholds: float | bool | None) -> VerifyReport:
    """Verify a run folder: simulate if RUN/sim/trace.npz is missing (`simulate_options`: robot, dt, timeout,
    seed), judge every criterion, write RUN/sim/verify.json. `thresholds` override VerifySettings fields
    (distance, near, passing, group_spread, goal_radius, deadlock_seconds, reaction_seconds, collisions_fail;
    defaults in verify/thresholds.py): an unknown name is a TypeError, a value out of range a ValueError."""
    settings = VerifySettings.with_overrides(settings, **thresholds)
    run = load_run(run_dir)
    if not run.folder.paths_path.is_file():
        raise InputFileError("no paths.json in this run", file=run.root,
                             hint="verify needs a generated run (socnavgen generate ... --out RUN)")
    loaded = run.location(location)  # once: the simulation and the checks share the object
    options = dict(simulate_options or {})
    options.setdefault("location", loaded)
    trace = load_trace(run, simulate_if_missing=simulate_if_missing, simulate_options=options)
    report = verify_trace(run, trace, location=loaded, settings=settings)
    made = _made_with(run, trace)
    robot = made.get("robot")
    if not report.passed and isinstance(robot, str) and robot != _default_robot() and \
            _default_verifies(run, loaded, settings, made):
        blame_the_policy(report, robot, int(made.get("seed", 0)))
    if write:
        atomic_write_text(run.folder.sim_dir / REPORT_FILE, report.model_dump_json(indent=2) + "\n")
    return report


def _default_robot() -> str:
    from socnavgen.sim import DEFAULT_ROBOT

    return DEFAULT_ROBOT


def _made_with(run: LoadedRun, trace: Trace) -> dict[str, Any]:
    """The robot and settings the trace was simulated with: RUN/sim/outputs.json's record, else the trace's
    meta (`robot_plugin`, seed, timeout, dt)."""
    from socnavgen.sim import recorded_options

    made = recorded_options(run.root)
    if made:
        return made
    meta = trace.meta if isinstance(trace.meta, dict) else {}
    found = {"robot": meta.get("robot_plugin"), "seed": meta.get("seed"), "timeout": meta.get("timeout"),
             "dt": getattr(trace, "dt", None)}
    return {k: v for k, v in found.items() if isinstance(v, str | int | float) and not isinstance(v, bool)}
