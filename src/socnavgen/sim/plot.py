"""Trajectory plot of a simulated run: the map and scene graph in world coordinates, the robot and every human
as coloured paths with start/end markers and time ticks, and the planned interaction points.

World coordinates come only from `location.transform`: the map image is drawn in pixel space and mapped to
the world by that affine transform, so flipped or rotated (nav2 origin yaw) maps come out right.
"""

from __future__ import annotations

import io
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.transforms import Affine2D  # noqa: E402

from socnavgen.safeio import atomic_write_bytes  # noqa: E402
from socnavgen.sim.trace import Trace  # noqa: E402

ROBOT_COLOR = "#d62728"  # red; no human uses it
HUMAN_COLORS = ("#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#17becf", "#8c564b", "#e377c2", "#bcbd22",
                "#7f7f7f", "#393b79")
INTERACTION_COLOR = "#ffbf00"
VIEW_MARGIN = 3.0  # m around the agents' trajectories


def human_color(index: int) -> str:
    return HUMAN_COLORS[index % len(HUMAN_COLORS)]


def map_corners_world(location: Any) -> np.ndarray:
    """World positions of the four outer corners of the map image (pixel centres are integers)."""
    w, h = location.image_size
    return location.transform.pixels_to_world(np.array([[-0.5, -0.5], [w - 0.5, -0.5], [w - 0.5, h - 0.5],
                                                        [-0.5, h - 0.5]]))


def draw_map(ax: Any, location: Any) -> None:
    """The map image, placed in the world by the location transform (any affine: flips, yaw)."""
    w, h = location.image_size
    image = ax.imshow(location.map_gray, cmap="gray", vmin=0, vmax=255, origin="upper",
                      extent=(-0.5, w - 0.5, h - 0.5, -0.5), interpolation="nearest", zorder=0)
    image.set_transform(Affine2D(location.transform.matrix) + ax.transData)


def draw_graph(ax: Any, location: Any, *, alpha: float = 0.35, labels: bool = True) -> None:
    """Scene-graph edges and nodes, faint, with node ids."""
    graph = location.scene_graph
    if not graph.nodes:
        return
    pos = {n.id: location.transform.pixel_to_world(*n.pos) for n in graph.nodes}
    for edge in graph.links:
        if edge.source in pos and edge.target in pos:
            (x0, y0), (x1, y1) = pos[edge.source], pos[edge.target]
            ax.plot([x0, x1], [y0, y1], color="#4a6fa5", lw=1.0, alpha=alpha, zorder=1)
    xy = np.array(list(pos.values()))
    ax.scatter(xy[:, 0], xy[:, 1], s=14, color="#4a6fa5", alpha=alpha + 0.2, zorder=2, linewidths=0)
    if labels:
        for node_id, (x, y) in pos.items():
            ax.annotate(node_id, (x, y), xytext=(3, 3), textcoords="offset points", fontsize=6, color="#2b4570",
                        alpha=min(1.0, alpha + 0.4), zorder=2)


def interaction_points(location: Any, plan: Any = None, trace: Trace | None = None) -> dict[str, tuple[float, float]]:
    """human name -> world position of its interaction point, from a PathPlan (or trace.meta)."""
    out: dict[str, tuple[float, float]] = {}
    if plan is not None:
        for human in plan.humans:
            if human.interaction_point:
                try:
                    out[human.name] = location.node_world(human.interaction_point)
                except KeyError:
                    continue
    elif trace is not None and isinstance(trace.meta.get("interaction_points"), dict):
        for name, point in trace.meta["interaction_points"].items():
            if isinstance(point, list | tuple) and len(point) == 2:
                out[name] = (float(point[0]), float(point[1]))
    return out


def view_limits(trace: Trace, location: Any, extra: Iterable[tuple[float, float]] = ()) -> tuple[float, ...]:
    """Axis limits: the agents' trajectories plus a margin, clipped to the map."""
    pts = [trace.robot[:, :2], trace.humans[:, :, :2].reshape(-1, 2)]
    extra = list(extra)
    if extra:
        pts.append(np.asarray(extra, dtype=float))
    xy = np.concatenate([p for p in pts if len(p)]) if any(len(p) for p in pts) else np.zeros((1, 2))
    corners = map_corners_world(location)
    lo = np.maximum(xy.min(axis=0) - VIEW_MARGIN, corners.min(axis=0))
    hi = np.minimum(xy.max(axis=0) + VIEW_MARGIN, corners.max(axis=0))
    if np.any(hi <= lo):
        lo, hi = corners.min(axis=0), corners.max(axis=0)
    return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])


def _figure_for(limits: tuple[float, ...], width_in: float, dpi: int) -> tuple[Any, Any]:
    x0, x1, y0, y1 = limits
    aspect = (y1 - y0) / max(x1 - x0, 1e-6)
    height_in = float(np.clip(width_in * aspect, 3.0, 12.0))
    fig, ax = plt.subplots(figsize=(width_in, height_in), dpi=dpi)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    return fig, ax


def _path_with_ticks(ax: Any, xy: np.ndarray, t: np.ndarray, color: str, label: str, tick_every: float) -> None:
    ax.plot(xy[:, 0], xy[:, 1], color=color, lw=2.0, label=label, zorder=4)
    ax.plot(*xy[0], marker="o", ms=8, color=color, mec="black", mew=0.8, zorder=5)
    ax.plot(*xy[-1], marker="s", ms=8, color=color, mec="black", mew=0.8, zorder=5)
    if tick_every <= 0 or len(t) < 2:
        return
    marks = np.arange(t[0] + tick_every, t[-1], tick_every)
    for mark in marks:
        i = int(np.searchsorted(t, mark))
        ax.plot(*xy[i], marker="|", ms=7, color=color, mew=1.5, zorder=5)
        ax.annotate(f"{mark:.0f}s", xy[i], xytext=(2, -8), textcoords="offset points", fontsize=6, color=color,
                    zorder=5)


def plot_trajectories(trace: Trace, location: Any, out_png: Path | str, *, plan: Any = None,
                      tick_every: float = 5.0, width_in: float = 8.0, dpi: int = 120) -> Path:
    """Write a PNG of the run: map, faint scene graph, robot and human paths (o start, s end, a tick every
    `tick_every` seconds), interaction points as stars. Returns the file path."""
    points = interaction_points(location, plan, trace)
    limits = view_limits(trace, location, points.values())
    fig, ax = _figure_for(limits, width_in, dpi)
    try:
        draw_map(ax, location)
        draw_graph(ax, location)
        for i, name in enumerate(trace.human_names):
            group = trace.group_ids[i] if i < len(trace.group_ids) else -1
            label = name + (f" (group {group})" if group != -1 else "")
            _path_with_ticks(ax, trace.humans[:, i, :2], trace.t, human_color(i), label, tick_every)
        _path_with_ticks(ax, trace.robot[:, :2], trace.t, ROBOT_COLOR, "robot", tick_every)
        if trace.robot_goal is not None:
            ax.plot(*trace.robot_goal, marker="X", ms=10, color=ROBOT_COLOR, mec="black", zorder=6, ls="none",
                    label="robot goal")
        for k, (name, (x, y)) in enumerate(points.items()):
            ax.plot(x, y, marker="*", ms=16, color=INTERACTION_COLOR, mec="black", zorder=6, ls="none",
                    label="interaction point" if k == 0 else None)
            ax.annotate(name, (x, y), xytext=(6, 6), textcoords="offset points", fontsize=7, zorder=6)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        reason = f", {trace.end_reason}" if trace.end_reason else ""
        duration = float(trace.t[-1] - trace.t[0]) if trace.steps else 0.0
        ax.set_title(f"{location.name}: {duration:.1f} s{reason}  (o start, s end, | every {tick_every:g} s)",
                     fontsize=9)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.85)
        fig.tight_layout()
        out = Path(out_png)
        out.parent.mkdir(parents=True, exist_ok=True)
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        atomic_write_bytes(out, buf.getvalue())
    finally:
        plt.close(fig)
    return out
