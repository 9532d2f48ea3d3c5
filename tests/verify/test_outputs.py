"""Trajectory PNG and GIF animation: files of the expected size with the agents really drawn."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from socnavgen.bt.library import HUMAN_GESTURES, ROBOT_GESTURES
from socnavgen.location import load_location
from socnavgen.run.folder import RunFolder
from socnavgen.sim.outputs.animate import _gesture_word, frame_indices, write_gif
from socnavgen.sim.outputs.plot import HUMAN_COLORS, INTERACTION_COLOR, ROBOT_COLOR, plot_trajectories

from .verify_builders import crossing_trace


def rgb(hex_color: str) -> np.ndarray:
    return np.array([int(hex_color[i:i + 2], 16) for i in (1, 3, 5)])


def near_color(img: np.ndarray, color: str, tol: int) -> np.ndarray:
    return np.all(np.abs(img[:, :, :3].astype(int) - rgb(color)) <= tol, axis=-1)


def test_trajectory_png(tmp_path: Path, give_way_run: Path, tiny_location: Path) -> None:
    loc = load_location(tiny_location)
    plan = RunFolder(give_way_run).read_paths()
    out = plot_trajectories(crossing_trace(), loc, tmp_path / "sim" / "trajectories.png", plan=plan)
    img = np.asarray(Image.open(out).convert("RGB"))
    assert img.shape[1] == 1050  # 7 in (a paper's full width) at 150 dpi
    robot = near_color(img, ROBOT_COLOR, 0)
    human = near_color(img, HUMAN_COLORS[0], 0)
    star = near_color(img, INTERACTION_COLOR, 0)
    assert robot.sum() > 200 and human.sum() > 200 and star.sum() > 20
    # The robot drives along y = 2.975 and the human along y = 3.975 (higher on the image): compare rows.
    assert np.nonzero(robot)[0].mean() > np.nonzero(human)[0].mean()
    # The map walls (black) are drawn.
    assert np.all(img < 30, axis=-1).sum() > 1000


def test_gif_frames_move_the_robot(tmp_path: Path, tiny_location: Path) -> None:
    loc = load_location(tiny_location)
    trace = crossing_trace()
    out = write_gif(trace, loc, tmp_path / "run.gif", fps=10)
    gif = Image.open(out)
    assert gif.n_frames == 21  # dt 0.5 s is slower than 10 fps: every step is a frame
    assert gif.info["duration"] == 100
    centroids = []
    for k in (0, gif.n_frames - 1):
        gif.seek(k)
        frame = np.asarray(gif.convert("RGB"))
        robot = near_color(frame, ROBOT_COLOR, 45)
        assert robot.sum() > 30
        centroids.append(np.nonzero(robot)[1].mean())
    assert centroids[1] > centroids[0] + 100  # the robot moved 9.5 m to the right (+x)


def test_gif_respects_max_frames(tmp_path: Path, tiny_location: Path) -> None:
    out = write_gif(crossing_trace(), load_location(tiny_location), tmp_path / "short.gif", max_frames=5)
    assert Image.open(out).n_frames == 5


def test_frame_selection() -> None:
    # 60 s at dt 0.05: real time at 10 fps is every 2nd step (600 frames) -> capped at 300 evenly spread
    idx = frame_indices(1201, 0.05, 10, 300)
    assert len(idx) == 300 and idx[0] == 0 and idx[-1] == 1200
    idx = frame_indices(101, 0.05, 10, 300)  # 5 s: every 2nd step plus the last
    assert list(idx[:3]) == [0, 2, 4] and idx[-1] == 100 and len(idx) == 51


@pytest.mark.parametrize(("table", "code", "word"), [(ROBOT_GESTURES, 4, "EXCUSE ME"), (HUMAN_GESTURES, 3, "EXCUSE ME"),
                                                     (ROBOT_GESTURES, 0, None), (HUMAN_GESTURES, 9, "gesture 9")])
def test_gesture_words(table, code, word) -> None:
    assert _gesture_word(table, code) == word
