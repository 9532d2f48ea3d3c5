"""Draw a location's scene graph on its map: the picture a vision LLM (and a person) reads.

The picture is cropped to the mapped part of the image, and node labels never overlap: a label with
no room on its node moves to the nearest free place (with a leader line), or is left out (thinned)
when none is near. Deterministic by construction: nearest-neighbour upscaling (Lanczos when shrinking), a font shipped with matplotlib,
colours chosen by the position of a type in the schema, no randomness and no timestamps.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from socnavgen.location.location import Location
from socnavgen.location.models import SceneGraph, Schema
from socnavgen.safeio import atomic_write_bytes

TARGET_LONG_SIDE = 1280  # px of map: large enough that 2-character labels stay legible for a vision model
MAX_LONG_SIDE = 1600  # px of the whole picture, legend included
LEGEND_WIDTH = 300

# Colour-blind-friendly, high-contrast palettes (Okabe-Ito first, then Tableau extras).
NODE_COLOURS = ["#E69F00", "#56B4E9", "#009E73", "#F0E442", "#CC79A7", "#0072B2", "#D55E00", "#999999",
                "#8DD3C7", "#FB8072", "#B3DE69", "#BC80BD", "#FFED6F", "#80B1D3"]
EDGE_COLOURS = ["#D62728", "#1F77B4", "#2CA02C", "#9467BD", "#FF7F0E", "#8C564B", "#E377C2", "#17BECF"]
UNKNOWN_TYPE_COLOUR = "#FF00FF"  # a type outside the schema: loud on purpose


@dataclass(frozen=True)
class Style:
    scale: float
    node_colour: dict[str, str]
    edge_colour: dict[str, str]


def _font(size: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    """DejaVu Sans Bold from matplotlib's data folder (a declared dependency), else Pillow's default."""
    try:
        import matplotlib

        path = Path(matplotlib.get_data_path()) / "fonts" / "ttf" / "DejaVuSans-Bold.ttf"
        return ImageFont.truetype(str(path), size)
    except Exception:  # font missing or FreeType unavailable
        return ImageFont.load_default()


def choose_scale(width: int, height: int, target: int = TARGET_LONG_SIDE, maximum: int = MAX_LONG_SIDE) -> float:
    """Scale bringing the map's long side to `target` px while the whole picture (map + legend) stays
    within `maximum` px: large enough for legible labels, small enough that no model shrinks it."""
    return min(target / max(width, height), (maximum - LEGEND_WIDTH) / width, maximum / height)


def type_colours(schema: Schema, graph: SceneGraph) -> tuple[dict[str, str], dict[str, str]]:
    node_colour = {t: NODE_COLOURS[i % len(NODE_COLOURS)] for i, t in enumerate(schema.node_types)}
    edge_colour = {t: EDGE_COLOURS[i % len(EDGE_COLOURS)] for i, t in enumerate(schema.edge_types)}
    for n in graph.nodes:
        node_colour.setdefault(n.type, UNKNOWN_TYPE_COLOUR)
    for e in graph.links:
        edge_colour.setdefault(e.type, UNKNOWN_TYPE_COLOUR)
    return node_colour, edge_colour


def _text_colour(hex_colour: str) -> str:
    r, g, b = (int(hex_colour[i:i + 2], 16) for i in (1, 3, 5))
    return "#000000" if 0.299 * r + 0.587 * g + 0.114 * b > 140 else "#FFFFFF"


@dataclass
class Layout:
    """Where things went in the picture: the crop of the map (image pixels), the scale, each node's
    label box (picture pixels, x0, y0, x1, y1), the nodes whose label had no free place (thinned) and the
    scale bar's box (no label covers it)."""

    crop: tuple[int, int, int, int]
    scale: float
    boxes: dict[str, tuple[float, float, float, float]]
    thinned: list[str]
    scale_bar: tuple[float, float, float, float] | None = None

    def at(self, pos: tuple[float, float]) -> tuple[float, float]:
        """Picture pixel of the centre of map pixel `pos`."""
        return ((pos[0] - self.crop[0] + 0.5) * self.scale, (pos[1] - self.crop[1] + 0.5) * self.scale)


def known_crop(gray: np.ndarray, graph: SceneGraph, margin: int | None = None) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of the mapped part of the image (the free floor and the walls around it, not
    unknown grey nor far specks of scan noise), with a small margin, always holding every node: the
    picture spends no space on unmapped surroundings."""
    from scipy import ndimage

    from socnavgen.location.occupancy import occupancy_from_image

    h, w = gray.shape
    occ = occupancy_from_image(gray)
    free = ~occ.blocked
    labels, count = ndimage.label(free, structure=np.ones((3, 3)))
    if count == 0:
        return 0, 0, w, h
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    # the mapped area: free floor large enough to matter (stray specks of scan noise far out are not)
    main = np.isin(labels, np.nonzero(sizes >= 0.1 * sizes.max())[0])
    known = ndimage.binary_dilation(main, iterations=3) & ~occ.unknown | main
    rows, cols = np.nonzero(known.any(axis=1))[0], np.nonzero(known.any(axis=0))[0]
    pad = margin if margin is not None else max(4, round(0.02 * max(w, h)))
    x0, y0, x1, y1 = cols[0] - pad, rows[0] - pad, cols[-1] + 1 + pad, rows[-1] + 1 + pad
    for n in graph.nodes:
        x0, y0 = min(x0, int(n.pos[0]) - pad), min(y0, int(n.pos[1]) - pad)
        x1, y1 = max(x1, int(n.pos[0]) + 1 + pad), max(y1, int(n.pos[1]) + 1 + pad)
    return max(0, x0), max(0, y0), min(w, x1), min(h, y1)


def _overlaps(a: tuple[float, float, float, float], b: tuple[float, float, float, float]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def place_labels(centres: dict[str, tuple[float, float]], sizes: dict[str, tuple[float, float]],
                 bounds: tuple[float, float], reserved: tuple[tuple[float, float, float, float], ...] = (),
                 ) -> tuple[dict[str, tuple[float, float, float, float]], list[str]]:
    """A box per label, none overlapping another or a `reserved` box (the scale bar): on its node when
    there is room, else the nearest free place around it (a leader line is drawn); a label with no free
    place nearby is thinned."""
    boxes: dict[str, tuple[float, float, float, float]] = {}
    thinned: list[str] = []
    directions = [(0, -1), (1, 0), (0, 1), (-1, 0), (1, -1), (1, 1), (-1, 1), (-1, -1)]
    for node_id in sorted(centres, key=lambda k: (centres[k][1], centres[k][0], k)):
        (cx, cy), (hw, hh) = centres[node_id], sizes[node_id]
        offsets = [(0.0, 0.0)] + [(dx * (hw + 3) * k, dy * (hh + 3) * k)
                                  for k in (1.0, 1.6, 2.2, 3.0, 4.0) for dx, dy in directions]
        for ox, oy in offsets:
            box = (cx + ox - hw, cy + oy - hh, cx + ox + hw, cy + oy + hh)
            inside = box[0] >= 0 and box[1] >= 0 and box[2] <= bounds[0] and box[3] <= bounds[1]
            if inside and not any(_overlaps(box, other) for other in (*boxes.values(), *reserved)):
                boxes[node_id] = box
                break
        else:
            thinned.append(node_id)
    return boxes, thinned


def render_with_layout(gray: np.ndarray, graph: SceneGraph, schema: Schema, *, title: str = "",
                       metres_per_pixel: float | None = None,
                       picture: np.ndarray | None = None) -> tuple[Image.Image, Layout]:
    """The map (grey levels kept, cropped to its mapped part), edges as coloured lines, nodes as labelled boxes
    that never overlap, a legend on the right; `picture`: the map in colour (an overhead view, same size as
    `gray`), drawn instead of the grey levels."""
    crop = known_crop(gray, graph)
    x0, y0, x1, y1 = crop
    view = gray[y0:y1, x0:x1]
    h, w = view.shape
    scale = choose_scale(w, h)
    if picture is not None and picture.shape[:2] == gray.shape:
        base = Image.fromarray(np.ascontiguousarray(picture[y0:y1, x0:x1]), mode="RGB")
    else:
        base = Image.fromarray(view, mode="L").convert("RGB")
    size = (max(1, round(w * scale)), max(1, round(h * scale)))
    resample = Image.Resampling.NEAREST if scale >= 1 else Image.Resampling.LANCZOS
    base = base.resize(size, resample)
    node_colour, edge_colour = type_colours(schema, graph)

    canvas = Image.new("RGB", (size[0] + LEGEND_WIDTH, max(size[1], 120 + 34 * (len(node_colour) + len(edge_colour)))),
                       "#FFFFFF")
    canvas.paste(base, (0, 0))
    draw = ImageDraw.Draw(canvas)
    layout = Layout(crop=crop, scale=scale, boxes={}, thinned=[])

    positions = {n.id: layout.at(n.pos) for n in graph.nodes}
    line_width = max(3, round(size[0] / 320))
    for e in graph.links:
        if e.source in positions and e.target in positions:
            draw.line([positions[e.source], positions[e.target]], fill=edge_colour[e.type], width=line_width)

    label_font = _font(max(14, round(max(size) / 60)))
    sizes = {}
    for n in graph.nodes:
        left, top, right, bottom = draw.textbbox((0, 0), n.id, font=label_font)
        sizes[n.id] = ((right - left) / 2 + 5, (bottom - top) / 2 + 4)
    bar = _scale_bar(size, scale, metres_per_pixel) if metres_per_pixel else None
    if bar:  # under the nodes: a node there keeps its dot, its label moves aside
        _draw_scale_bar(draw, size, *bar)
        layout.scale_bar = bar[2]
    layout.boxes, layout.thinned = place_labels(positions, sizes, (size[0], size[1]), (bar[2],) if bar else ())
    dot = max(4, line_width + 1)
    for n in graph.nodes:  # nodes whose label moved or was thinned keep a dot at their true place
        cx, cy = positions[n.id]
        box = layout.boxes.get(n.id)
        if box is not None and abs((box[0] + box[2]) / 2 - cx) < 0.5 and abs((box[1] + box[3]) / 2 - cy) < 0.5:
            continue
        if box is not None:
            draw.line([(cx, cy), ((box[0] + box[2]) / 2, (box[1] + box[3]) / 2)], fill="#000000", width=2)
        draw.ellipse([cx - dot, cy - dot, cx + dot, cy + dot], fill=node_colour[n.type], outline="#000000", width=2)
    for n in graph.nodes:
        box = layout.boxes.get(n.id)
        if box is None:
            continue
        colour = node_colour[n.type]
        draw.rectangle(list(box), fill=colour, outline="#000000", width=2)
        draw.text(((box[0] + box[2]) / 2, (box[1] + box[3]) / 2), n.id, fill=_text_colour(colour), font=label_font,
                  anchor="mm")

    _draw_legend(draw, size[0], node_colour, edge_colour, title, line_width)
    return canvas, layout


def _draw_legend(draw: ImageDraw.ImageDraw, x0: int, node_colour: dict[str, str], edge_colour: dict[str, str],
                 title: str, line_width: int) -> None:
    head, body = _font(20), _font(16)
    x, y = x0 + 14, 12
    if title:
        draw.text((x, y), title[:26], fill="#000000", font=head)
        y += 34
    draw.text((x, y), "Node types", fill="#000000", font=head)
    y += 30
    for name, colour in node_colour.items():
        draw.rectangle([x, y, x + 34, y + 22], fill=colour, outline="#000000", width=2)
        draw.text((x + 46, y + 11), name, fill="#000000", font=body, anchor="lm")
        y += 32
    y += 10
    draw.text((x, y), "Edge types", fill="#000000", font=head)
    y += 30
    for name, colour in edge_colour.items():
        draw.line([(x, y + 11), (x + 34, y + 11)], fill=colour, width=line_width + 1)
        draw.text((x + 46, y + 11), name, fill="#000000", font=body, anchor="lm")
        y += 32


def _scale_bar(size: tuple[int, int], scale: float, metres_per_pixel: float,
               ) -> tuple[int, float, tuple[float, float, float, float]]:
    """(metres, length in picture pixels, box) of a 1/2/5/10 m bar in the lower-left corner."""
    image_px_per_metre = scale / metres_per_pixel
    metres = next((m for m in (1, 2, 5, 10, 20, 50, 100) if m * image_px_per_metre >= size[0] / 10), 100)
    length = metres * image_px_per_metre
    x, y = 12, size[1] - 18
    return metres, length, (x - 6, y - 26, x + length + 6, y + 10)


def _draw_scale_bar(draw: ImageDraw.ImageDraw, size: tuple[int, int], metres: int, length: float,
                    box: tuple[float, float, float, float]) -> None:
    """The scale bar, so distances can be read off the picture (labels keep clear of its box)."""
    x, y = 12, size[1] - 18
    draw.rectangle(list(box), fill="#FFFFFF")
    draw.line([(x, y), (x + length, y)], fill="#000000", width=4)
    draw.text((x + length / 2, y - 4), f"{metres} m", fill="#000000", font=_font(16), anchor="mb")


def render_location(location: Location) -> Image.Image:
    return render_location_with_layout(location)[0]


def render_location_with_layout(location: Location) -> tuple[Image.Image, Layout]:
    try:
        mpp = location.transform.meters_per_pixel
    except Exception:  # a broken transform must not stop the picture; `location check` reports it
        mpp = None
    gray, picture = location.map_gray, _colour_map(location)
    if location.config.occupancy_image:  # `map` is a picture: crop by where the walls are, draw the picture
        from socnavgen.location.occupancy import load_image_gray
        from socnavgen.safeio import contained_path

        occupancy_gray = load_image_gray(contained_path(location.root, location.config.occupancy_image))
        if occupancy_gray.shape == gray.shape:
            picture = picture if picture is not None else np.repeat(gray[:, :, None], 3, axis=2)
            gray = occupancy_gray
    return render_with_layout(gray, location.scene_graph, location.schema, title=location.name,
                              metres_per_pixel=mpp, picture=picture)


def _colour_map(location: Location) -> np.ndarray | None:
    """The map image as RGB when it is a colour picture (an overhead view), else None."""
    try:
        with Image.open(location.map_path) as img:
            if img.mode not in ("RGB", "RGBA", "P"):
                return None
            return np.asarray(img.convert("RGB"))
    except Exception:  # the grey map was already read (and checked) by map_gray; a picture is optional
        return None


def png_bytes(image: Image.Image) -> bytes:
    buffer = io.BytesIO()
    image.save(buffer, format="PNG", optimize=False)
    return buffer.getvalue()


def write_location_png(location: Location, out: Path) -> Path:
    atomic_write_bytes(out, png_bytes(render_location(location)))
    return out
