"""One episode = one scenario x one robot policy x one seed -> one table row.

Runs inside a worker (a local process, a Ray worker, or the calling process). Each worker keeps every
location and world it loaded (WORKER_CACHE), so an episode costs the simulation, not the map loading.
A policy that raises, returns garbage, calls sys.exit or runs past the wall-clock limit fails its episode only;
the limit covers everything the episode does (loading, simulation, metrics, verification). A worker that dies
(os._exit, the OOM killer) or never comes back is the executor's to handle (executors.py)."""

from __future__ import annotations

import json
import math
import signal
import threading
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from socnavgen.campaign.scenarios import Scenario
from socnavgen.text import count

# what each verifier finding keeps in the row (fields a verifier version lacks are simply left out)
VERDICT_FIELDS = {"name", "kind", "passed", "required", "human", "criterion", "robustness", "blame", "blame_human"}
TRAJECTORY_BYTES = "_trajectory"  # the row's trajectory file (bytes): the store writes it beside the table


class EpisodeTimeout(BaseException):
    """The episode ran past its wall-clock limit. A BaseException, like KeyboardInterrupt, so that a policy
    retrying inside `except Exception` does not swallow it."""


@dataclass(frozen=True)
class EpisodeSettings:
    dt: float = 0.05
    timeout: float | None = None  # s; None: the scenario's route decides (WorkerCache.time_limit)
    throttle: bool = True
    wall_timeout: float = 30.0
    verify: bool = True
    metrics: tuple[str, ...] | None = None  # None = all
    vary_people: bool = True  # draw each person's traits from the seed (campaign/variation.py)
    trajectory_hz: float = 10.0  # keep the episode's trajectories at this rate (0: none); sim/outputs/trajectory.py


@dataclass(frozen=True)
class Episode:
    scenario: Scenario
    policy: str  # the policy's name in the campaign
    robot: str  # its plugin spec
    seed: int
    inputs: str | None = None  # digest of what decides it (fingerprint.py), stored in its row
    params: tuple[tuple[str, Any], ...] = ()  # the policy's params, sorted (sim.robot.api.robot_from)

    @property
    def key(self) -> str:
        return episode_key(self.scenario.id, self.policy, self.seed)


def episode_key(scenario: str, policy: str, seed: int) -> str:
    return f"{scenario}|{policy}|{seed}"


@dataclass
class WorkerCache:
    """What a worker keeps between episodes: locations and worlds by folder, and each scenario's run folder
    read once (a LoadedRun, handed to both the simulator and the verifier; run folders do not change
    during a campaign)."""

    locations: dict[str, Any] = field(default_factory=dict)
    worlds: dict[str, Any] = field(default_factory=dict)
    runs: dict[str, Any] = field(default_factory=dict)
    default_verified: dict[tuple[str, int, str], bool] = field(default_factory=dict)  # (run, seed, settings)
    limits: dict[tuple[str, float], Any] = field(default_factory=dict)  # (run, dt) -> TimeLimit
    loads: int = 0  # how many locations this worker loaded (tests check it stays at one per location)

    def run(self, run_dir: str) -> Any:
        """The scenario's LoadedRun (its files are read on first use, then kept)."""
        if run_dir not in self.runs:
            from socnavgen.run.loaded import LoadedRun

            self.runs[run_dir] = LoadedRun(Path(run_dir))
        return self.runs[run_dir]

    def time_limit(self, scenario: Scenario, dt: float) -> Any:
        """The scenario's TimeLimit: what `simulate` gives the default robot on its route (the same for every
        policy; sim.engine.scenario.route_time_limit)."""
        if (scenario.run_dir, dt) not in self.limits:
            from socnavgen.sim.engine.scenario import route_time_limit

            location, _ = self.location(scenario.location_dir)
            self.limits[scenario.run_dir, dt] = route_time_limit(self.run(scenario.run_dir), location, dt)
        return self.limits[scenario.run_dir, dt]

    def location(self, location_dir: str) -> tuple[Any, Any]:
        if location_dir not in self.locations:
            from socnavgen.location import load_location
            from socnavgen.sim import World

            location = load_location(Path(location_dir))
            self.locations[location_dir] = location
            self.worlds[location_dir] = World.from_location(location)
            self.loads += 1
        return self.locations[location_dir], self.worlds[location_dir]


WORKER_CACHE = WorkerCache()


class _Deadline:
    """Raise EpisodeTimeout after `seconds` of wall time: by SIGALRM when we are the main thread (catches a
    policy stuck inside one act() call), and at every progress callback otherwise. The alarm repeats every
    REFIRE seconds until the episode is left, so a policy that swallows the first one meets the next; one that
    swallows every BaseException is stopped with its worker process (executors.py)."""

    REFIRE = 0.2

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds
        self.end = time.perf_counter() + seconds
        self._armed = False

    def __enter__(self) -> _Deadline:
        if threading.current_thread() is threading.main_thread() and hasattr(signal, "setitimer"):
            self._previous = signal.signal(signal.SIGALRM, self._fire)
            signal.setitimer(signal.ITIMER_REAL, self.seconds, self.REFIRE)
            self._armed = True
        return self

    def _fire(self, signum: int, frame: Any) -> None:  # noqa: ARG002 - signal handler signature
        raise EpisodeTimeout(f"episode exceeded its wall-clock limit of {self.seconds:g} s")

    def check(self, k: int = 0, n: int = 0) -> None:  # noqa: ARG002 - progress callback signature
        if time.perf_counter() > self.end:
            self._fire(0, None)

    def __exit__(self, *exc: object) -> None:
        if self._armed:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, self._previous)


def _identity(ep: Episode) -> dict[str, Any]:
    s = ep.scenario
    return {"episode": ep.key, "scenario": s.id, "location": s.location, "card": s.card, "source": s.source,
            "humans": s.humans, "policy": ep.policy, "robot": ep.robot, "seed": ep.seed, "inputs": ep.inputs,
            "params": json.dumps(dict(ep.params), sort_keys=True), "robot_body": _body_of(ep)}


def _body_of(ep: Episode) -> str | None:
    """The robot's kinematics and limits as JSON (None when the params do not make a robot)."""
    from socnavgen.errors import SocnavgenError
    from socnavgen.sim.robot.api import BODY_PARAMS
    from socnavgen.sim.robot.body import RobotBody

    try:
        body = RobotBody(**{BODY_PARAMS[k]: v for k, v in ep.params if k in BODY_PARAMS})
    except (SocnavgenError, ValueError, TypeError):
        return None
    return json.dumps(body.meta(), sort_keys=True)


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if hasattr(value, "item"):
        return _finite(value.item())
    return value


def simulate_episode(ep: Episode, settings: EpisodeSettings, cache: WorkerCache | None = None,
                     deadline: _Deadline | None = None) -> tuple[Any, Any, Any]:
    """(trace, location, world) of one episode, using the worker's cached location and world."""
    from socnavgen.sim import SimConfig, ThrottleConfig, load_simulation, robot_from

    cache = cache or WORKER_CACHE
    location, world = cache.location(ep.scenario.location_dir)
    policy, body = robot_from(ep.robot, dict(ep.params))
    run = cache.run(ep.scenario.run_dir)
    limit = cache.time_limit(ep.scenario, settings.dt) if settings.timeout is None else None
    timeout = limit.seconds if limit is not None else settings.timeout
    sim = load_simulation(run, policy, SimConfig(dt=settings.dt, timeout=timeout, seed=ep.seed, body=body),
                          ThrottleConfig(enabled=settings.throttle), location=location, world=world)
    if limit is not None:
        sim.timeout_why = f"the scenario's route: {limit.why}"
    sim.meta["robot_plugin"] = ep.robot
    if settings.vary_people:
        from socnavgen.campaign.variation import apply_traits, draw_people, people_of

        traits = draw_people(ep.scenario.id, ep.seed, *people_of(run))
        apply_traits(sim, traits)
        sim.meta["people_traits"] = {n: t.model_dump() for n, t in traits.items()}
    return sim.run(progress=deadline.check if deadline else None), location, world


def run_episode(ep: Episode, settings: EpisodeSettings, cache: WorkerCache | None = None) -> dict[str, Any]:
    """The episode's row: identity, outcome, every chosen metric, the verifier's verdicts."""
    cache = cache or WORKER_CACHE
    row = _identity(ep)
    warm_up_compiled()
    start = time.perf_counter()
    try:
        with _Deadline(settings.wall_timeout) as deadline:
            measured = _measure(ep, settings, cache, deadline)
    except EpisodeTimeout as exc:
        return failed_row(ep, f"timeout: {exc}", time.perf_counter() - start)
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - a policy's crash (even sys.exit) fails its episode
        return failed_row(ep, f"crash: {type(exc).__name__}: {exc} ({_where(exc)})", time.perf_counter() - start)
    row.update(measured, wall_seconds=time.perf_counter() - start)
    return row


def _measure(ep: Episode, settings: EpisodeSettings, cache: WorkerCache, deadline: _Deadline) -> dict[str, Any]:
    """Simulate, measure and verify one episode: the row's outcome, metrics and verdicts (all of it under the
    episode's deadline; nothing of it is kept when the episode fails)."""
    from socnavgen.campaign.columns import contact_free
    from socnavgen.sim.metric_definitions import all_metric_names
    from socnavgen.sim.metrics import compute_metrics, navigation_metrics
    from socnavgen.sim.social_metrics import social_metrics

    row: dict[str, Any] = {}
    trace, location, world = simulate_episode(ep, settings, cache, deadline)
    metrics = compute_metrics(trace, location)
    metrics.update(navigation_metrics(trace, world))
    metrics["success"] = bool(contact_free(metrics["success"], metrics.get("static_obstacle_collisions")))
    metrics.update(social_metrics(trace, world, success=bool(metrics["success"])))
    metrics["expected_behaviour"], details = expected_behaviour(ep, trace, cache)
    chosen = settings.metrics or all_metric_names()
    row.update({m: _finite(metrics.get(m)) for m in chosen})
    row["success"] = bool(metrics["success"])
    row["expected_checks"] = json.dumps(details) if details else None
    row.update(_people(trace))
    if settings.trajectory_hz > 0:
        from socnavgen.sim.outputs.trajectory import trajectory_bytes

        row[TRAJECTORY_BYTES] = trajectory_bytes(trace, settings.trajectory_hz)
    row.update(status="ok", end_reason=trace.end_reason, steps=int(trace.steps),
               sim_seconds=float(trace.t[-1]) if trace.steps else 0.0)
    if settings.verify:
        from socnavgen.verify.runner import blame_the_policy, verify_trace

        report = verify_trace(cache.run(ep.scenario.run_dir), trace, location=location)
        if _is_default(ep):  # this is the episode _default_verifies would simulate: its verdict, kept
            cache.default_verified.setdefault(_default_key(ep, settings), bool(report.passed))
        elif not report.passed and _default_verifies(ep, settings, cache, deadline):
            blame_the_policy(report, ep.policy, ep.seed)  # the scenario happens with the default robot
        row["verified"] = bool(report.passed)
        row["verify_failed"] = "; ".join(f.name for f in report.failures)
        row["verdicts"] = json.dumps([f.model_dump(mode="json", include=VERDICT_FIELDS) for f in report.findings])
    row["failure_reason"] = None if row["success"] else _why_not(metrics, trace)
    return row


def _default_robot() -> str:
    from socnavgen.sim import DEFAULT_ROBOT

    return DEFAULT_ROBOT


def _is_default(ep: Episode) -> bool:
    return ep.robot == _default_robot() and not ep.params


def _default_key(ep: Episode, settings: EpisodeSettings) -> tuple[str, int, str]:
    """WorkerCache.default_verified's key of an episode's scenario and seed: the scenario's run folder and the
    settings too (the worker cache outlives a campaign in its process, and the same card in another campaign -
    another folder, other settings - may verify differently)."""
    return str(ep.scenario.run_dir), ep.seed, repr(settings)


def _default_verifies(ep: Episode, settings: EpisodeSettings, cache: WorkerCache, deadline: _Deadline) -> bool:
    """Whether the scenario verifies with the default robot on this seed (simulated and verified once per
    worker, scenario and seed, or kept from the default robot's own episode of that seed when the campaign ran
    it in this worker first; blame in a campaign falls on the policy under test when it does)."""
    key = _default_key(ep, settings)
    if key not in cache.default_verified:
        from socnavgen.verify.runner import verify_trace

        default = Episode(ep.scenario, _default_robot(), _default_robot(), ep.seed)
        trace, location, _ = simulate_episode(default, settings, cache, deadline)
        cache.default_verified[key] = bool(verify_trace(cache.run(ep.scenario.run_dir), trace,
                                                        location=location).passed)
    return cache.default_verified[key]


def _people(trace: Any) -> dict[str, Any]:
    """The row's record of this seed's people (campaign/variation.py), when they were drawn."""
    from socnavgen.campaign.variation import Traits, summary

    traits = trace.meta.get("people_traits") if isinstance(trace.meta, dict) else None
    return summary({n: Traits(**t) for n, t in traits.items()}) if traits else {}


def expected_behaviour(ep: Episode, trace: Any, cache: WorkerCache) -> tuple[float | None, list[dict[str, Any]]]:
    """The card's expected-behaviour checks on this trace (sim/behaviour_checks.py), at the place of the
    scenario's first encounter; (None, []) for a scenario that is no card or whose card states no check."""
    from socnavgen.cards.library import card_names, get_card
    from socnavgen.sim.behaviour_checks import check_behaviour

    if not ep.scenario.card or ep.scenario.card not in card_names():
        return None, []
    checks = get_card(ep.scenario.card).expected_checks
    if not checks:
        return None, []
    spec = cache.run(ep.scenario.run_dir).spec()
    place = None
    if spec is not None and spec.encounters and spec.encounters[0].node:
        location, _ = cache.location(ep.scenario.location_dir)
        place = complex(*location.node_world(spec.encounters[0].node))
    return check_behaviour(trace, checks, place, None)


def warm_up_compiled() -> None:
    """The compiled simulator ready in this worker before its first episode's clock starts (numba compiles it
    on a new machine: ~40 s that are no episode's fault)."""
    from socnavgen.sim import warm_up

    warm_up()


def _why_not(metrics: dict[str, Any], trace: Any) -> str:
    reasons = []
    if metrics.get("collisions"):
        reasons.append(f"collision with a person ({count(int(metrics['collisions']), 'step')} in contact)")
    if metrics.get("static_obstacle_collisions"):
        reasons.append(f"touched a wall ({count(int(metrics['static_obstacle_collisions']), 'time')}, "
                       f"{metrics.get('min_obstacle_clearance') or 0.0:+.2f} m at the closest)")
    if not metrics.get("completed") and trace.end_reason != "robot_goal":
        reasons.append(f"goal not reached ({trace.end_reason})")
    return "; ".join(reasons) or "goal not reached"


def _where(exc: BaseException) -> str:
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return "no traceback"
    last = frames[-1]
    return f"{Path(last.filename).name}:{last.lineno}"


def failed_row(ep: Episode, reason: str, wall_seconds: float | None = None) -> dict[str, Any]:
    """The row of a failed episode (it crashed, timed out, or its worker died or was stopped): identity and
    why; no metric."""
    return {**_identity(ep), "status": "failed", "failure_reason": reason[:500], "end_reason": "error",
            "success": False, "wall_seconds": wall_seconds}


def run_batch(episodes: list[Episode], settings: EpisodeSettings) -> list[dict[str, Any]]:
    """Rows of several episodes in this worker (the unit of work sent to a process or a Ray task)."""
    return [run_episode(ep, settings) for ep in episodes]
