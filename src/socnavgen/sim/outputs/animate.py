"""GIF animation of a simulated run: the map and scene graph, agents as discs with a heading line, gestures
as speech bubbles (words from the node library's gesture tables), the action each human's tree executes,
and the time. Contact is drawn, not left to the eye: an agent in contact (sim.contact's one definition: a gap
of at most bodies.CONTACT_MARGIN with the robot or another person) at any step since the previous frame gets a
thick CONTACT_COLOR outline, and every disc has a white rim of RIM_PX so that bodies apart show a gap (round 14's
hospital_07: 0.19 m between two people is 5 px at 27 px/m; with trail lines through it and the GIF scaled down in a
montage, the eyes saw the discs overlap). The static picture is drawn once with matplotlib; agents are painted on a copy per frame with
Pillow (redrawing the figure per frame was ~10x slower). The trace is subsampled to at most `max_frames`
frames so the file size and the render time stay bounded.
"""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from socnavgen.bt.library import HUMAN_GESTURES, ROBOT_GESTURES
from socnavgen.safeio import atomic_write_bytes
from socnavgen.sim import contact
from socnavgen.sim.outputs.labels import LabelPlacer
from socnavgen.sim.outputs.plot import (
    INTERACTION_COLOR,
    ROBOT_COLOR,
    _figure_for,
    axes_placer,
    draw_graph,
    draw_map,
    graph_points,
    human_color,
    interaction_points,
    legend_below,
    place_text,
    plt,
    view_limits,
)
from socnavgen.sim.trace import YAW, Trace, X, Y

FONT_PX = 11  # caption / bubble font size in pixels
HEADER_PX = 26  # white strip above the map for the clock (never clipped, never over the data)
RIM_PX = 2  # white rim round every disc: two bodies apart never share a pixel of outline
CONTACT_COLOR = (255, 0, 255)  # outline of an agent in contact (no agent or map colour is magenta)
CONTACT_PX = 3  # its width


def contact_marks(trace: Trace, idx: np.ndarray) -> np.ndarray:
    """(frames, humans + 1) bool: which agents (the humans, then the robot) were in contact with the robot or
    another person (sim.contact) at any step since the previous drawn frame, so a touch between two frames of a
    subsampled GIF is still shown."""
    steps, n = trace.steps, len(trace.human_names)
    touch = np.zeros((steps, n + 1), dtype=bool)
    if n:
        robot = contact.in_contact(contact.trace_gaps(trace))
        touch[:, :n] |= robot
        touch[:, n] = contact.row_any(robot)
        gaps, pairs = contact.people_gaps(trace)
        for c, (i, j) in enumerate(pairs):
            hit = contact.in_contact(gaps[:, c])
            touch[:, i] |= hit
            touch[:, j] |= hit
    seen = np.concatenate([np.zeros((1, n + 1), dtype=int), np.cumsum(touch, axis=0)])  # contacts in steps [0, k)
    idx = np.asarray(idx, dtype=int)
    start = np.concatenate([[0], idx[:-1] + 1]) if len(idx) else idx
    return (seen[idx + 1] - seen[np.minimum(start, idx)]) > 0


def scale_length(view_width_m: float) -> float:
    """A round scale-bar length, about a fifth of the view."""
    target = max(view_width_m / 5.0, 1e-3)
    magnitude = 10 ** math.floor(math.log10(target))
    return next(m * magnitude for m in (5, 2, 1) if m * magnitude <= target)


def frame_indices(steps: int, dt: float, fps: float, max_frames: int) -> np.ndarray:
    """Trace steps to draw: real-time playback at `fps` when that fits in `max_frames`, else evenly spread."""
    if steps <= 0:
        return np.zeros(0, dtype=int)
    stride = max(1, int(round(1.0 / (fps * dt)))) if dt > 0 else 1
    idx = np.arange(0, steps, stride)
    if len(idx) > max_frames:
        idx = np.unique(np.linspace(0, steps - 1, max_frames).round().astype(int))
    if idx[-1] != steps - 1 and len(idx) < max_frames:
        idx = np.append(idx, steps - 1)
    return idx


def _gesture_word(table: dict[int, str], code: int) -> str | None:
    if code == 0:
        return None
    return table.get(int(code), f"gesture {int(code)}")


def _font(size: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    """DejaVu Sans from matplotlib's own fonts (always installed with it), else Pillow's default."""
    try:
        from matplotlib import font_manager

        return ImageFont.truetype(font_manager.findfont("DejaVu Sans", fallback_to_default=True), size)
    except (OSError, ValueError):
        try:
            return ImageFont.load_default(size=size)
        except TypeError:  # Pillow < 10.1 has only the fixed bitmap font
            return ImageFont.load_default()


def _rgb(color: str) -> tuple[int, int, int]:
    return tuple(int(color[i:i + 2], 16) for i in (1, 3, 5))  # type: ignore[return-value]


class _Canvas:
    """The static picture (map, graph, paths, goal, interaction points) rendered once by matplotlib, and the
    world -> image pixel mapping of its axes, so each frame only paints the agents (fast, with Pillow)."""

    def __init__(self, trace: Trace, location: Any, plan: Any, width_in: float, dpi: int) -> None:
        points = interaction_points(location, plan, trace)
        limits = view_limits(trace, location, points.values())
        fig, ax = _figure_for(limits, width_in, dpi)
        try:
            draw_map(ax, location)
            draw_graph(ax, location, alpha=0.25, labels=False)
            for k, (x, y) in enumerate(points.values()):
                ax.plot(x, y, marker="*", ms=12, color=INTERACTION_COLOR, mec="black", zorder=3, ls="none",
                        label="interaction point" if k == 0 else None)
            if trace.robot_goal is not None:
                ax.plot(*trace.robot_goal, marker="o", ms=13, mfc="none", mec=ROBOT_COLOR, mew=2, zorder=3,
                        ls="none", label="robot goal")
            for i, name in enumerate(trace.human_names):  # faint full paths for context
                ax.plot(trace.humans[:, i, 0], trace.humans[:, i, 1], color=human_color(i), lw=0.8, alpha=0.35,
                        zorder=3)
                ax.plot([], [], marker="o", color=human_color(i), mec="black", ls="none", label=name)
            ax.plot(trace.robot[:, 0], trace.robot[:, 1], color=ROBOT_COLOR, lw=0.8, alpha=0.35, zorder=3)
            ax.plot([], [], marker="o", color=ROBOT_COLOR, mec="black", ls="none", label="robot")
            ax.set_xticks([])
            ax.set_yticks([])
            from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

            bar = scale_length(limits[1] - limits[0])
            ax.add_artist(AnchoredSizeBar(ax.transData, bar, f"{bar:g} m", "lower right", pad=0.4, sep=3,
                                          frameon=True, size_vertical=bar / 40, fontproperties={"size": 8}))
            fig.tight_layout(rect=(0, legend_below(fig, ax, ncol=5), 1, 1))
            placer = axes_placer(ax)
            for node_id, (x, y) in graph_points(location).items():
                place_text(ax, placer, (x, y), node_id, fontsize=6, color="#2b4570", alpha=0.7, zorder=2)
            fig.canvas.draw()
            body = Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy())
            self.to_display = ax.transData.frozen()
        finally:
            plt.close(fig)
        # a header strip for the clock above the picture
        self.background = Image.new("RGB", (body.width, body.height + HEADER_PX), (255, 255, 255))
        self.background.paste(body, (0, HEADER_PX))
        self.height = body.height  # of the figure: pixel() maps into it, then shifts by the header
        self.offset = HEADER_PX
        origin = self.to_display.transform((0.0, 0.0))
        self.px_per_m = float(np.linalg.norm(self.to_display.transform((1.0, 0.0)) - origin))
        self.font = _font(FONT_PX)
        self.clock_font = _font(FONT_PX + 2)

    def pixel(self, x: float, y: float) -> tuple[float, float]:
        dx, dy = self.to_display.transform((x, y))
        return float(dx), float(self.height - dy) + self.offset  # display y grows up, image rows down

    def rim(self, draw: ImageDraw.ImageDraw, x: float, y: float, radius: float) -> None:
        """The white rim under a disc (drawn for every agent before any disc: a rim never covers a body)."""
        cx, cy = self.pixel(x, y)
        r = max(2.0, radius * self.px_per_m) + RIM_PX
        draw.ellipse((cx - r, cy - r, cx + r, cy + r), fill=(255, 255, 255))

    def agent(self, draw: ImageDraw.ImageDraw, x: float, y: float, yaw: float, radius: float, color: str,
              touching: bool = False) -> None:
        cx, cy = self.pixel(x, y)
        r = max(2.0, radius * self.px_per_m)
        outline, width = (CONTACT_COLOR, CONTACT_PX) if touching else ((0, 0, 0), 1)
        draw.ellipse((cx - r, cy - r, cx + r, cy + r), fill=_rgb(color), outline=outline, width=width)
        # the heading line ends at the disc's edge: one sticking out of the body (it reached 1.4 radii) drew into the
        # gap to the next body and read as the two touching
        hx, hy = self.pixel(x + radius * math.cos(yaw), y + radius * math.sin(yaw))
        draw.line((cx, cy, hx, hy), fill=(0, 0, 0), width=2)

    def caption(self, draw: ImageDraw.ImageDraw, placer: LabelPlacer, x: float, y: float, radius: float,
                text: str) -> None:
        """The agent's caption below it, or beside/above it when that is taken; left out if nowhere is free."""
        cx, cy = self.pixel(x, y)
        r = radius * self.px_per_m + 2
        x0, y0, x1, y1 = draw.textbbox((0, 0), text, font=self.font)
        w, h = x1 - x0 + 2, y1 - y0 + 2
        box = placer.place(cx, cy, w, h, offsets=((-0.5, 0.0), (-0.5, -1.0), (0.0, -0.5), (-1.0, -0.5)),
                           clearance=r)
        if box is None:
            return
        draw.rectangle(box, fill=(255, 255, 255))
        draw.text((box[0] + 1 - x0, box[1] + 1 - y0), text, font=self.font, fill=(0, 0, 0))

    def bubble(self, draw: ImageDraw.ImageDraw, x: float, y: float, radius: float, text: str, left: bool) -> None:
        cx, cy = self.pixel(x, y)
        r = radius * self.px_per_m
        ax_, ay_ = (cx - r, cy - r) if left else (cx + r, cy - r)
        anchor = "rd" if left else "ld"
        tx, ty = (ax_ - 6, ay_ - 6) if left else (ax_ + 6, ay_ - 6)
        box = draw.textbbox((tx, ty), text, font=self.font, anchor=anchor)
        pad = 3
        draw.line((ax_, ay_, tx, ty), fill=(0, 0, 0), width=1)
        draw.rounded_rectangle((box[0] - pad, box[1] - pad, box[2] + pad, box[3] + pad), radius=4,
                               fill=(255, 255, 255), outline=(0, 0, 0), width=1)
        draw.text((tx, ty), text, font=self.font, fill=(0, 0, 0), anchor=anchor)

    def clock(self, draw: ImageDraw.ImageDraw, t: float) -> None:
        """The time, in the header strip (the strip is white: nothing to clip or cover)."""
        draw.text((8, HEADER_PX // 2), f"t = {t:.1f} s", font=self.clock_font, fill=(0, 0, 0), anchor="lm")


def _render_frames(trace: Trace, location: Any, idx: np.ndarray, plan: Any, width_in: float,
                   dpi: int) -> list[Image.Image]:
    canvas = _Canvas(trace, location, plan, width_in, dpi)
    touching = contact_marks(trace, idx)
    frames = []
    for f, k in enumerate(idx):
        img = canvas.background.copy()
        draw = ImageDraw.Draw(img)
        placer = LabelPlacer(bounds=(0, HEADER_PX, img.width, img.height))
        speech: list[tuple[float, float, float, str, bool]] = []
        agents: list[tuple[str, float, float, float, float, str]] = [
            (name, float(trace.humans[k, i, X]), float(trace.humans[k, i, Y]), float(trace.humans[k, i, YAW]),
             float(trace.human_radii[i]), human_color(i)) for i, name in enumerate(trace.human_names)]
        agents.append(("robot", float(trace.robot[k, X]), float(trace.robot[k, Y]), float(trace.robot[k, YAW]),
                       float(trace.robot_radius), ROBOT_COLOR))
        for _name, x, y, _yaw, radius, _color in agents:
            canvas.rim(draw, x, y, radius)
        for a, (_name, x, y, yaw, radius, color) in enumerate(agents):  # discs first: captions keep off every agent
            canvas.agent(draw, x, y, yaw, radius, color, bool(touching[f, a]))
            placer.reserve_point(*canvas.pixel(x, y), radius * canvas.px_per_m)
        for i, name in enumerate(trace.human_names):
            _, x, y, _yaw, radius, _ = agents[i]
            act = int(trace.action[k, i])
            action = trace.node_names[act] if 0 <= act < len(trace.node_names) else "-"
            canvas.caption(draw, placer, x, y, radius, f"{name}: {action}")
            word = _gesture_word(HUMAN_GESTURES, int(trace.human_gesture[k, i]))
            if word:
                speech.append((x, y, radius, word, False))
        _, x, y, _yaw, radius, _ = agents[-1]
        canvas.caption(draw, placer, x, y, radius, "robot")
        word = _gesture_word(ROBOT_GESTURES, int(trace.robot_gesture[k]))
        if word:  # the robot speaks to the upper left, humans to the upper right
            speech.append((x, y, float(trace.robot_radius), word, True))
        for bx, by, br, text, left in speech:  # bubbles last: on top of everything
            canvas.bubble(draw, bx, by, br, text, left)
        canvas.clock(draw, float(trace.t[k]))
        frames.append(img)
    return frames


def write_gif(trace: Trace, location: Any, out_gif: Path | str, *, fps: float = 10, max_frames: int = 300,
              plan: Any = None, width_in: float = 6.4, dpi: int = 100) -> Path:
    """Write an animated GIF of the run (at most `max_frames` frames at `fps`). Returns the file path."""
    idx = frame_indices(trace.steps, float(trace.dt), fps, max_frames)
    if len(idx) == 0:
        raise ValueError("the trace has no steps to animate")
    frames = _render_frames(trace, location, idx, plan, width_in, dpi)
    # One shared palette (from the first frame) keeps colours stable between frames and the file small; the contact
    # outline's colour is added to it (a first frame without contact would map it onto a neighbour's colour).
    palette_source = frames[0].quantize(colors=254, method=Image.Quantize.MEDIANCUT)
    palette = (palette_source.getpalette() or [])[:254 * 3]
    palette_source.putpalette(palette + [0] * (254 * 3 - len(palette)) + list(CONTACT_COLOR))
    paletted = [f.quantize(palette=palette_source, dither=Image.Dither.NONE) for f in frames]
    buf = io.BytesIO()
    paletted[0].save(buf, format="GIF", save_all=True, append_images=paletted[1:], duration=int(round(1000 / fps)),
                     loop=0, optimize=False, disposal=1)
    out = Path(out_gif)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(out, buf.getvalue())
    return out


def mp4_available() -> bool:
    """Whether MP4 can be written: the ffmpeg binary the imageio-ffmpeg package ships (a dependency)."""
    try:
        import imageio_ffmpeg

        return bool(imageio_ffmpeg.get_ffmpeg_exe())
    except (ImportError, RuntimeError):
        return False


def write_mp4(trace: Trace, location: Any, out_mp4: Path | str, *, fps: float = 10, max_frames: int = 1200,
              plan: Any = None, width_in: float = 6.4, dpi: int = 100) -> Path:
    """Write the animation as an H.264 MP4 (the same frames as the GIF, full colour, real time at `fps`) with the
    ffmpeg of imageio-ffmpeg; a SocnavgenError saying so when that package is missing."""
    from socnavgen.errors import SocnavgenError

    if not mp4_available():
        raise SocnavgenError("MP4 needs the imageio-ffmpeg package (its ffmpeg binary)",
                             hint="pip install imageio-ffmpeg, or write the GIF only")
    import tempfile

    import imageio_ffmpeg

    idx = frame_indices(trace.steps, float(trace.dt), fps, max_frames)
    if len(idx) == 0:
        raise ValueError("the trace has no steps to animate")
    frames = _render_frames(trace, location, idx, plan, width_in, dpi)
    w, h = frames[0].size
    size = (w + w % 2, h + h % 2)  # H.264 with yuv420p wants even sides
    out = Path(out_mp4)
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out.parent) as tmp:
        part = Path(tmp) / out.name
        writer = imageio_ffmpeg.write_frames(str(part), size, fps=fps, codec="libx264", pix_fmt_out="yuv420p",
                                             macro_block_size=1, ffmpeg_log_level="error",
                                             output_params=["-movflags", "+faststart"])
        writer.send(None)
        for frame in frames:
            canvas = Image.new("RGB", size, "white")
            canvas.paste(frame.convert("RGB"), (0, 0))
            writer.send(canvas.tobytes())
        writer.close()
        atomic_write_bytes(out, part.read_bytes())
    return out
