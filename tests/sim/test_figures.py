"""Figures a researcher can put in a paper: labels never overlap, a person standing still gets one time
label (not "10s15s20s"), the legend sits outside the map, the GIF has a header clock, a legend and a scale."""

from __future__ import annotations

import itertools
import random
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from socnavgen.cards.generate import write_card_run
from socnavgen.sim import simulate_run
from socnavgen.sim.outputs.animate import HEADER_PX, scale_length, write_gif
from socnavgen.sim.outputs.labels import LabelPlacer, overlaps
from socnavgen.sim.outputs.plot import plt, trajectory_figure

REPO = Path(__file__).resolve().parents[2]


def test_placer_never_returns_overlapping_boxes() -> None:
    rng = random.Random(3)
    placer = LabelPlacer(bounds=(0, 0, 300, 200))
    placed = [b for _ in range(300) if (b := placer.place(rng.uniform(0, 300), rng.uniform(0, 200), 30, 10))]
    assert 10 < len(placed) < 300  # some fit, the rest are left out rather than piled up
    assert not any(overlaps(a, b, pad=0.0) for a, b in itertools.combinations(placed, 2))
    assert all(b[0] >= 0 and b[2] <= 300 and b[1] >= 0 and b[3] <= 200 for b in placed)


def test_placer_keeps_clear_of_a_marker() -> None:
    placer = LabelPlacer()
    placer.reserve_point(100, 100, 8)
    box = placer.place(100, 100, 20, 10, clearance=9)
    assert box is not None and not overlaps(box, (92, 92, 108, 108), pad=0.0)


def test_scale_bar_lengths_are_round() -> None:
    assert scale_length(12.0) == 2.0 and scale_length(60.0) == 10.0 and scale_length(3.0) == 0.5


@pytest.fixture(scope="module")
def crowd_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("fig") / "crowd"
    write_card_run("crowd-navigation", REPO / "examples" / "locations" / "hospital", out)
    simulate_run(out, timeout=40.0)
    return out


def test_trajectory_figure_labels_never_overlap_and_legend_is_outside(crowd_run: Path) -> None:
    from socnavgen.run import RunFolder
    from socnavgen.sim.trace import Trace

    run = RunFolder(crowd_run)
    fig = trajectory_figure(Trace.load(run.sim_dir / "trace.npz"), run.location())
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        ax = fig.axes[0]
        boxes = [t.get_window_extent(renderer) for t in ax.texts]
        assert len(boxes) > 5  # node ids, time labels, the interaction point's name
        clashes = [(ax.texts[a].get_text(), ax.texts[b].get_text())
                   for a, b in itertools.combinations(range(len(boxes)), 2) if boxes[a].overlaps(boxes[b])]
        assert clashes == []
        legend = fig.legends[0].get_window_extent(renderer)
        assert legend.y1 <= ax.get_window_extent(renderer).y0  # below the map, not over the data
    finally:
        plt.close(fig)


def test_someone_standing_still_gets_one_time_label() -> None:
    from socnavgen.sim.outputs.plot import _ticks, axes_placer

    fig, ax = plt.subplots()
    try:
        ax.set_xlim(-5, 5)
        ax.set_ylim(-5, 5)
        t = np.arange(0, 30, 0.5)
        xy = np.zeros((len(t), 2))  # stands at the origin for 30 s
        _ticks(ax, axes_placer(ax), xy, t, "#000000", 5.0)
        assert [text.get_text() for text in ax.texts] == ["5s"]
    finally:
        plt.close(fig)


def test_gif_has_header_clock_and_is_bounded(crowd_run: Path, tmp_path: Path) -> None:
    from socnavgen.run import RunFolder
    from socnavgen.sim.trace import Trace

    run = RunFolder(crowd_run)
    out = write_gif(Trace.load(run.sim_dir / "trace.npz"), run.location(), tmp_path / "a.gif", max_frames=20)
    with Image.open(out) as gif:
        assert gif.n_frames <= 20
        gif.seek(gif.n_frames - 1)
        frame = np.asarray(gif.convert("RGB"))
    header = frame[:HEADER_PX]
    assert (header < 100).any(axis=2).any()  # the clock's dark text is in the header strip
    assert (header[:, -40:] > 200).all()  # and nothing else is: the strip is white on its right end


def test_library_and_verify_simulations_write_what_simulate_writes(tmp_path: Path) -> None:
    """sim has a public face: simulate_run (and verify on a run not yet simulated) leave metrics.json and the
    plot beside the trace, exactly like `socnavgen simulate`."""
    import json

    from socnavgen.verify import verify_run

    run = tmp_path / "fa"
    write_card_run("frontal-approach", REPO / "examples" / "locations" / "warehouse", run)
    verify_run(run)
    sim = run / "sim"
    assert {"trace.npz", "metrics.json", "trajectories.png", "verify.json"} <= {p.name for p in sim.iterdir()}
    assert "time_to_reach_goal" in json.loads((sim / "metrics.json").read_text())


def test_metrics_json_carries_units_and_definitions(tmp_path: Path) -> None:
    import json

    run = tmp_path / "fa"
    write_card_run("frontal-approach", REPO / "examples" / "locations" / "warehouse", run)
    simulate_run(run, timeout=30.0, plot=False)
    data = json.loads((run / "sim" / "metrics.json").read_text())
    definitions = data.pop("definitions")
    assert set(definitions) == set(data)  # every metric written is defined
    assert definitions["minimum_distance_to_people"]["unit"] == "m"
    assert definitions["collisions"]["unit"] and definitions["path_efficiency"]["formula"]
    assert "path_irregularity" in data and "static_obstacle_collisions" in data


def test_the_trajectory_figure_is_drawn_once_when_written(crowd_run: Path, tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """Writing the figure renders it once: tight_layout's leftover layout engine made savefig draw everything
    (map resampling, every text's layout) a second time first, a third of the plot's time."""
    from matplotlib.figure import Figure

    from socnavgen.run import RunFolder
    from socnavgen.sim.outputs.plot import plot_trajectories
    from socnavgen.sim.trace import Trace

    draws = []
    draw = Figure.draw
    monkeypatch.setattr(Figure, "draw", lambda fig, renderer: (draws.append(fig), draw(fig, renderer))[1])
    run = RunFolder(crowd_run)
    for fmt in ("png", "svg"):
        draws.clear()
        out = plot_trajectories(Trace.load(run.sim_dir / "trace.npz"), run.location(), tmp_path / f"t.{fmt}")
        assert out.stat().st_size > 1000 and len(draws) == 1, (fmt, len(draws))
