"""The files a simulation leaves in RUN/sim/ besides the trace: metrics.json, trajectories.png and (on
request) animation.gif. One public function, so a simulation started from Python, from `verify` or from a
campaign writes exactly what `socnavgen simulate` writes."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

METRICS_FILE = "metrics.json"
PLOT_FILE = "trajectories.png"
GIF_FILE = "animation.gif"


@dataclass
class SimOutputs:
    """What was written, and the metrics themselves (name -> value)."""

    metrics: dict[str, Any]
    files: dict[str, Path] = field(default_factory=dict)


def write_outputs(trace: Any, location: Any, out_dir: Path | str, *, plot: bool = True,
                  gif: bool = False) -> SimOutputs:
    """Write metrics.json (+ trajectories.png, + animation.gif) for `trace` into `out_dir`.

    `location` is the loaded Location the trace was simulated on (pass the object: it is not re-read)."""
    from socnavgen.sim.metrics import compute_metrics, navigation_metrics, write_metrics
    from socnavgen.sim.world import World

    out = Path(out_dir)
    metrics = {**compute_metrics(trace, location), **navigation_metrics(trace, World.from_location(location))}
    files = {"metrics": out / METRICS_FILE}
    write_metrics(metrics, files["metrics"])
    if plot:
        from socnavgen.sim.outputs.plot import plot_trajectories

        files["plot"] = out / PLOT_FILE
        plot_trajectories(trace, location, files["plot"])
    if gif:
        from socnavgen.sim.outputs.animate import write_gif

        files["gif"] = out / GIF_FILE
        write_gif(trace, location, files["gif"])
    return SimOutputs(metrics=metrics, files=files)
