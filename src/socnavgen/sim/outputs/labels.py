"""Text labels that never overlap: a greedy placer over boxes in display pixels, shared by the trajectory
plot (matplotlib) and the GIF (Pillow). Each label tries a few positions around its anchor and takes the
first one that is free; a label with no free position is left out rather than drawn over another."""

from __future__ import annotations

from collections.abc import Iterable

Box = tuple[float, float, float, float]  # x0, y0, x1, y1 with x0 < x1, y0 < y1

# Offsets (in units of the label's own width / height) tried around the anchor, nearest first.
AROUND: tuple[tuple[float, float], ...] = ((0.15, 0.15), (0.15, -1.15), (-1.15, 0.15), (-1.15, -1.15),
                                           (-0.5, 0.6), (-0.5, -1.6), (0.15, -0.5), (-1.15, -0.5))


def overlaps(a: Box, b: Box, pad: float = 1.0) -> bool:
    return a[0] < b[2] + pad and b[0] < a[2] + pad and a[1] < b[3] + pad and b[1] < a[3] + pad


class LabelPlacer:
    """Reserve boxes (labels, markers) and find free places for new labels."""

    def __init__(self, bounds: Box | None = None, pad: float = 1.0) -> None:
        self.bounds = bounds
        self.pad = pad
        self.boxes: list[Box] = []

    def reserve(self, box: Box) -> None:
        self.boxes.append(box)

    def reserve_point(self, x: float, y: float, radius: float) -> None:
        """Keep labels off a marker of `radius` pixels at (x, y)."""
        self.boxes.append((x - radius, y - radius, x + radius, y + radius))

    def is_free(self, box: Box) -> bool:
        if self.bounds is not None:
            x0, y0, x1, y1 = self.bounds
            if box[0] < x0 or box[1] < y0 or box[2] > x1 or box[3] > y1:
                return False
        return not any(overlaps(box, other, self.pad) for other in self.boxes)

    def place(self, x: float, y: float, width: float, height: float,
              offsets: Iterable[tuple[float, float]] = AROUND, clearance: float = 0.0) -> Box | None:
        """The first free box of size (width, height) near (x, y) (y grows the way the caller's does), at
        least `clearance` pixels off the anchor (a marker's radius), reserved; None when all positions collide."""
        for fx, fy in offsets:
            cx = clearance * ((fx > -0.5) - (fx < -0.5))
            cy = clearance * ((fy > -0.5) - (fy < -0.5))
            x0, y0 = x + fx * width + cx, y + fy * height + cy
            box = (x0, y0, x0 + width, y0 + height)
            if self.is_free(box):
                self.boxes.append(box)
                return box
        return None
