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
from socnavgen.sim.outputs.labels import LabelPlacer  # noqa: E402
from socnavgen.sim.trace import Trace  # noqa: E402

ROBOT_COLOR = "#d62728"  # red; no human uses it
HUMAN_COLORS = ("#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#17becf", "#8c564b", "#e377c2", "#bcbd22",
                "#7f7f7f", "#393b79")
INTERACTION_COLOR = "#ffbf00"
VIEW_MARGIN = 1.5  # m around the agents' trajectories
STILL = 0.3  # m: a time tick is labelled only if the agent moved this far since the last labelled tick


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


def graph_points(location: Any) -> dict[str, tuple[float, float]]:
    """Node id -> world position (through the location's transform, the only pixel->world conversion)."""
    return {n.id: location.transform.pixel_to_world(*n.pos) for n in location.scene_graph.nodes}


def draw_graph(ax: Any, location: Any, *, alpha: float = 0.35, labels: bool = True,
               placer: LabelPlacer | None = None) -> None:
    """Scene-graph edges and nodes, faint, with node ids (left out where they would overlap other labels)."""
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
        placer = placer or LabelPlacer()
        for node_id, (x, y) in pos.items():
            place_text(ax, placer, (x, y), node_id, fontsize=6, color="#2b4570", alpha=min(1.0, alpha + 0.4),
                       zorder=2)


def place_text(ax: Any, placer: LabelPlacer, xy: tuple[float, float], text: str, *, fontsize: float,
               clearance: float = 0.0, **style: Any) -> bool:
    """Draw `text` next to world point `xy` where it overlaps nothing already placed (its size measured by
    the renderer); False if left out. Call after the axes' layout is final."""
    x, y = ax.transData.transform(xy)
    label = ax.text(0, 0, text, fontsize=fontsize, ha="left", va="bottom", clip_on=True, **style)
    extent = label.get_window_extent(ax.figure.canvas.get_renderer())
    ox, oy = ax.transData.transform((0.0, 0.0))  # where the text's anchor is now, to know its box offset
    box = placer.place(float(x), float(y), extent.width + 1.0, extent.height, clearance=clearance)
    if box is None:
        label.remove()
        return False
    label.set_position(ax.transData.inverted().transform((box[0] - (extent.x0 - ox), box[1] - (extent.y0 - oy))))
    return True


def axes_placer(ax: Any) -> LabelPlacer:
    """A placer bounded by the axes' box in display pixels (the equal aspect applied first: matplotlib would
    otherwise move the axes at draw time, after the labels were placed)."""
    ax.apply_aspect()
    bbox = ax.get_window_extent()
    return LabelPlacer(bounds=(bbox.x0, bbox.y0, bbox.x1, bbox.y1))


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
    """Axis limits: the agents' trajectories, the robot's waypoints and goal (never cropped out, even when the
    robot did not get there) plus a margin, clipped to the map."""
    pts = [trace.robot[:, :2], trace.humans[:, :, :2].reshape(-1, 2),
           np.asarray(list(trace.robot_waypoints) + ([trace.robot_goal] if trace.robot_goal is not None else []),
                      dtype=float).reshape(-1, 2)]
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


def _path(ax: Any, xy: np.ndarray, color: str, label: str) -> None:
    ax.plot(xy[:, 0], xy[:, 1], color=color, lw=2.0, label=label, zorder=4)
    ax.plot(*xy[0], marker="o", ms=8, color=color, mec="black", mew=0.8, zorder=5, ls="none")
    ax.plot(*xy[-1], marker="s", ms=8, color=color, mec="black", mew=0.8, zorder=5, ls="none")


def _ticks(ax: Any, placer: LabelPlacer, xy: np.ndarray, t: np.ndarray, color: str, tick_every: float) -> None:
    """A tick every `tick_every` s; its label only where the agent moved since the last label and the label
    overlaps nothing (a person standing still for 20 s gets one label, not "10s15s20s")."""
    if tick_every <= 0 or len(t) < 2:
        return
    last: np.ndarray | None = None
    for mark in np.arange(t[0] + tick_every, t[-1], tick_every):
        i = min(int(np.searchsorted(t, mark)), len(xy) - 1)
        ax.plot(*xy[i], marker="|", ms=7, color=color, mew=1.5, zorder=5)
        if last is not None and np.hypot(*(xy[i] - last)) < STILL:
            continue
        if place_text(ax, placer, (float(xy[i, 0]), float(xy[i, 1])), f"{mark:.0f}s", fontsize=7, color=color,
                      zorder=5):
            last = xy[i]


def legend_below(fig: Any, ax: Any, ncol: int = 4) -> float:
    """The legend in a strip under the axes (never over the data, never over the axis label); returns the
    figure fraction the strip takes, for tight_layout's rect."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return 0.0
    ncol = min(ncol, len(handles))
    rows = -(-len(handles) // ncol)
    strip = min(0.4, (rows * 0.2 + 0.12) / fig.get_figheight())
    fig.legend(handles, labels, loc="lower center", ncol=ncol, fontsize=7, frameon=False)
    return strip


def plot_trajectories(trace: Trace, location: Any, out_file: Path | str, *, plan: Any = None,
                      tick_every: float = 5.0, width_in: float = 7.0, dpi: int = 150) -> Path:
    """Write the run's figure (see trajectory_figure) as PNG, SVG or PDF, by the file's suffix. At the default
    7 in (a paper's full width) its smallest text is 7 pt. Returns the file path."""
    fig = trajectory_figure(trace, location, plan=plan, tick_every=tick_every, width_in=width_in, dpi=dpi)
    try:
        out = Path(out_file)
        fmt = out.suffix.lstrip(".").lower() or "png"
        out.parent.mkdir(parents=True, exist_ok=True)
        buf = io.BytesIO()
        fig.savefig(buf, format=fmt, metadata={"Date": None} if fmt in ("svg", "pdf") else None)
        atomic_write_bytes(out, buf.getvalue())
    finally:
        plt.close(fig)
    return out


def trajectory_figure(trace: Trace, location: Any, *, plan: Any = None, tick_every: float = 5.0,
                      width_in: float = 8.0, dpi: int = 120) -> Any:
    """The run as a matplotlib Figure: map, faint scene graph with node ids, robot and human paths (o start,
    s end, a tick every `tick_every` seconds), the robot's goal as a ring, interaction points as stars, the
    legend below the map; labels never overlap. The caller closes it."""
    points = interaction_points(location, plan, trace)
    limits = view_limits(trace, location, points.values())
    fig, ax = _figure_for(limits, width_in, dpi)
    try:
        draw_map(ax, location)
        draw_graph(ax, location, labels=False)
        paths = []
        for i, name in enumerate(trace.human_names):
            group = trace.group_ids[i] if i < len(trace.group_ids) else -1
            label = name + (f" (group {group})" if group != -1 else "")
            paths.append((trace.humans[:, i, :2], human_color(i)))
            _path(ax, paths[-1][0], human_color(i), label)
        paths.append((trace.robot[:, :2], ROBOT_COLOR))
        _path(ax, trace.robot[:, :2], ROBOT_COLOR, "robot")
        if trace.robot_goal is not None:  # a ring: the end markers inside it stay visible
            ax.plot(*trace.robot_goal, marker="o", ms=16, mfc="none", mec=ROBOT_COLOR, mew=2.2, zorder=7,
                    ls="none", label="robot goal")
        for k, (x, y) in enumerate(points.values()):
            ax.plot(x, y, marker="*", ms=15, color=INTERACTION_COLOR, mec="black", zorder=6, ls="none",
                    label="interaction point" if k == 0 else None)
        ax.plot([], [], marker="o", color="grey", mec="black", ls="none", label="start")
        ax.plot([], [], marker="s", color="grey", mec="black", ls="none", label="end")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        reason = f", {trace.end_reason.replace('_', ' ')}" if trace.end_reason else ""
        duration = float(trace.t[-1] - trace.t[0]) if trace.steps else 0.0
        ax.set_title(f"{location.name}: {duration:.1f} s{reason}; ticks every {tick_every:g} s", fontsize=9)
        fig.tight_layout(rect=(0, legend_below(fig, ax), 1, 1))
        fig.set_layout_engine(None)  # laid out once: with tight_layout's placeholder, savefig draws all twice
        # labels last, with the layout final: markers first, then names, time labels, node ids
        placer = axes_placer(ax)

        def reserve(point: Any, radius: float) -> None:  # a world point's marker, in pixels
            px, py = ax.transData.transform(point)
            placer.reserve_point(px, py, radius=radius)

        for xy, _ in paths:
            for end in (xy[0], xy[-1]):
                reserve(end, 6)
        for x, y in points.values():
            reserve((x, y), 8)
        if trace.robot_goal is not None:  # no label under the goal ring
            reserve(trace.robot_goal, 12)
        for name, (x, y) in points.items():
            place_text(ax, placer, (x, y), name, fontsize=7, clearance=9, zorder=6)
        for xy, color in paths:
            _ticks(ax, placer, xy, trace.t, color, tick_every)
        for node_id, (x, y) in graph_points(location).items():
            place_text(ax, placer, (x, y), node_id, fontsize=7, color="#2b4570", alpha=0.85, zorder=2)
    except BaseException:
        plt.close(fig)
        raise
    return fig
