"""The files a simulation leaves in RUN/sim/ (or `simulate --out DIR`) besides the trace: metrics.json,
trajectories.png (and on request .svg / .pdf) and, on request, animation.gif and animation.mp4. One public
function, so a simulation started from Python, from `verify` or from a campaign writes exactly what
`socnavgen simulate` writes."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

METRICS_FILE = "metrics.json"
PLOT_FILE = "trajectories.png"
GIF_FILE = "animation.gif"
MP4_FILE = "animation.mp4"
FIGURE_FORMATS = ("png", "svg", "pdf")  # what the trajectory figure can be written as


@dataclass
class SimOutputs:
    """What was written, and the metrics themselves (name -> value)."""

    metrics: dict[str, Any]
    files: dict[str, Path] = field(default_factory=dict)


def write_outputs(trace: Any, location: Any, out_dir: Path | str, *, plot: bool = True, gif: bool = False,
                  formats: tuple[str, ...] = ("png",), mp4: bool = False) -> SimOutputs:
    """Write metrics.json (+ the trajectory figure in each of `formats`, + animation.gif, + animation.mp4) for
    `trace` into `out_dir`.

    `location` is the loaded Location the trace was simulated on (pass the object: it is not re-read)."""
    from socnavgen.sim.metrics import compute_metrics, navigation_metrics, write_metrics
    from socnavgen.sim.social_metrics import social_metrics
    from socnavgen.sim.world import World

    out = Path(out_dir)
    world = World.from_location(location)
    metrics = {**compute_metrics(trace, location), **navigation_metrics(trace, world)}
    metrics.update(social_metrics(trace, world, success=bool(metrics.get("success"))))
    files = {"metrics": out / METRICS_FILE}
    write_metrics(metrics, files["metrics"])
    if plot:
        from socnavgen.sim.outputs.plot import plot_trajectories

        for fmt in formats:
            key = "plot" if fmt == "png" else f"plot_{fmt}"
            files[key] = plot_trajectories(trace, location, (out / PLOT_FILE).with_suffix(f".{fmt}"))
    if gif:
        from socnavgen.sim.outputs.animate import write_gif

        files["gif"] = out / GIF_FILE
        write_gif(trace, location, files["gif"])
    if mp4:
        from socnavgen.sim.outputs.animate import write_mp4

        files["mp4"] = write_mp4(trace, location, out / MP4_FILE)
    return SimOutputs(metrics=metrics, files=files)


# -- RUN/sim/ as one set: what the outputs were made from, so a stale or half-written set is never taken ----
# outputs.json is written last: without it (or with other digests) the outputs do not count; verify.json (written
# by `verify`) judged one trace, so it goes when the trace is replaced. The names live with the run folder.
from socnavgen.run.verification import RECORD as STAMP_FILE  # noqa: E402
from socnavgen.run.verification import REPORT as VERIFY_FILE  # noqa: E402
from socnavgen.run.verification import TRACE as TRACE_FILE  # noqa: E402

OURS = (STAMP_FILE, VERIFY_FILE, TRACE_FILE, METRICS_FILE, PLOT_FILE, GIF_FILE, MP4_FILE, "trajectories.svg",
        "trajectories.pdf")


@dataclass(frozen=True)
class MadeFrom:
    """How a trace was made: the robot plugin and the simulation settings (the run's and location's files,
    the policy's source and socnavgen's version are recorded beside them as digests)."""

    robot: str
    dt: float
    timeout: float
    seed: int
    throttle: bool = True


def _digests(run_root: Path, location: Any, robot: str) -> dict[str, Any]:
    from socnavgen.run.digest import RUN_FILES, files_digest, location_digest, policy_digest, version

    names = [*RUN_FILES, *(f"behaviors/{p.name}" for p in sorted((run_root / "behaviors").glob("*.xml")))]
    return {"run": {n: files_digest(run_root, [n]) for n in names}, "location": location_digest(location),
            "policy": policy_digest(robot), "version": version()}


def folder_identity(path: Path | str) -> tuple[int, int]:
    """(device, inode) of a folder: the same folder even if renamed; another one if replaced."""
    st = Path(path).stat()
    return st.st_dev, st.st_ino


def save_run_outputs(trace: Any, location: Any, run_root: Path | str, made: MadeFrom, *,
                     identity: tuple[int, int] | None = None, plot: bool = True, gif: bool = False,
                     out_dir: Path | str | None = None, formats: tuple[str, ...] = ("png",),
                     mp4: bool = False) -> SimOutputs:
    """Replace RUN/sim/ (or `out_dir`: `simulate --out`, so that two robots on one run keep their own sets) with
    the outputs of `trace`: outputs.json first says a set is being written, the earlier
    set (and the verify.json that judged it) is removed, the new files written, and outputs.json last records
    what this trace was made from. A kill in between leaves outputs.json saying the set is incomplete, which
    `stale_reason` reports and `verify` never takes for a finished set.

    `identity` (folder_identity of the run folder when the simulation started) refuses to write when the run
    folder was moved or replaced meanwhile, instead of recreating its old path."""
    import hashlib
    import json

    from socnavgen.errors import SocnavgenError
    from socnavgen.safeio import atomic_write_json

    root = Path(run_root)
    try:
        same = identity is None or folder_identity(root) == identity
    except OSError:
        same = False
    if not same:
        raise SocnavgenError(f"the run folder {root} was moved, renamed or deleted during the simulation; "
                             "nothing was written", hint="simulate it again where it is now")
    out = root / "sim" if out_dir is None else Path(out_dir)
    out.mkdir(exist_ok=True, parents=out_dir is not None)  # the run folder itself is never recreated
    atomic_write_json(out / STAMP_FILE, {"complete": False})
    for name in OURS[1:]:
        (out / name).unlink(missing_ok=True)
    record: dict[str, Any] = {"complete": True, **_digests(root, location, made.robot)}
    trace.save(out / TRACE_FILE)
    written = write_outputs(trace, location, out, plot=plot, gif=gif, formats=formats, mp4=mp4)
    files = {TRACE_FILE: out / TRACE_FILE, **{p.name: p for p in written.files.values()}}
    record.update(made=json.loads(json.dumps(made.__dict__)),
                  files={n: hashlib.sha256(p.read_bytes()).hexdigest() for n, p in files.items()})
    atomic_write_json(out / STAMP_FILE, record)
    written.files = {"trace": out / TRACE_FILE, **written.files}
    return written


def read_stamp(run_root: Path | str) -> dict[str, Any] | None:
    from socnavgen.safeio import load_json_file

    path = Path(run_root) / "sim" / STAMP_FILE
    if not path.is_file():
        return None
    try:
        data = load_json_file(path)
    except Exception:  # noqa: BLE001 - an unreadable record is no record
        return None
    return data if isinstance(data, dict) else None


def recorded_options(run_root: Path | str) -> dict[str, Any]:
    """The robot and settings RUN/sim/trace.npz was simulated with (empty when unknown): what to simulate
    again with when the trace is stale."""
    stamp = read_stamp(run_root) or {}
    made = stamp.get("made")
    if not isinstance(made, dict):
        return {}
    return {k: made[k] for k in ("robot", "dt", "timeout", "seed", "throttle")
            if isinstance(made.get(k), str | int | float | bool)}


def stale_reason(run_root: Path | str, location: Any) -> str | None:
    """Why RUN/sim/trace.npz is not the run's current simulation, or None: its outputs were being written when
    the process stopped, the trace is not the one recorded, a run or location file changed since, the robot
    policy's source changed, or another socnavgen version made it. A trace with no outputs.json at all (made
    by hand or by a socnavgen before these records) is None here: `unrecorded` tells that case."""
    import hashlib

    root = Path(run_root)
    stamp = read_stamp(root)
    if stamp is None:
        return None
    if stamp.get("complete") is not True:
        return f"the simulation that wrote {root / 'sim'} was interrupted before its outputs were complete"
    files = got if isinstance(got := stamp.get("files"), dict) else {}
    trace = root / "sim" / TRACE_FILE
    if not trace.is_file() or files.get(TRACE_FILE) != hashlib.sha256(trace.read_bytes()).hexdigest():
        return f"{trace} is not the trace {STAMP_FILE} records (replaced or half-written)"
    made = got if isinstance(got := stamp.get("made"), dict) else {}
    now = _digests(root, location, str(made.get("robot", "")))
    then_run = got if isinstance(got := stamp.get("run"), dict) else {}
    changed = sorted(n for n in set(now["run"]) | set(then_run) if now["run"].get(n) != then_run.get(n))
    if changed:
        return f"{', '.join(changed)} changed since {trace} was simulated"
    if now["location"] != stamp.get("location"):
        return f"the location's files changed since {trace} was simulated"
    if now["policy"] != stamp.get("policy"):
        return f"the robot policy's source ({made.get('robot')}) changed since {trace} was simulated"
    if now["version"] != stamp.get("version"):
        return f"{trace} was simulated by socnavgen {stamp.get('version')}, this is {now['version']}"
    return None


def unrecorded(run_root: Path | str) -> bool:
    """RUN/sim/trace.npz exists without outputs.json: made by hand or by an older socnavgen (judged as it is)."""
    sim = Path(run_root) / "sim"
    return (sim / TRACE_FILE).is_file() and not (sim / STAMP_FILE).exists()
