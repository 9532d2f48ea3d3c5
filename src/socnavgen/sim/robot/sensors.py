"""What a robot would sense beyond the Observation's state: a 2D range scan (a planar laser) and the route ahead
along the planner's global path. Plain numpy on the World's occupancy grid (nothing compiled): the Gymnasium
env (campaign.gym_env) observes them, and a policy of the user's may call them too.

* `range_scan`: `beams` rays from the robot's centre, beam 0 along its heading and the others counter-clockwise
  at equal angles; each reads the distance to the first blocked map cell (or off the map) or the first person
  disc it meets, whichever is nearer, and `max_range` where it meets nothing. Walls are sampled every half map
  cell, so a range is the wall's surface to within half a cell.
* `route_ahead`: the next `count` points, `spacing` metres apart, of the way the planner would take from the
  robot's position: down the cost-to-go field of the current waypoint (robot.fields: the field the built-in
  robots and robot.route.Route follow), then from that waypoint down the next one's field, and so on to the
  goal; the goal repeats once the way is shorter than count x spacing.
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen.sim.world.grid import World

NOBODY = np.zeros(0, complex)


def beam_directions(yaw: float, beams: int) -> np.ndarray:
    """(beams,) unit complex directions: beam 0 along `yaw`, then counter-clockwise every 2 pi / beams."""
    return np.exp(1j * (yaw + 2.0 * np.pi * np.arange(beams) / beams))


def range_scan(world: World, origin: complex, yaw: float, beams: int, max_range: float,
               people: np.ndarray = NOBODY, radii: np.ndarray = NOBODY) -> np.ndarray:
    """(beams,) float32 metres to the nearest wall or person disc along each beam (see the module's docstring);
    `people`: complex positions, `radii` their radii (m)."""
    directions = beam_directions(yaw, beams)
    step = 0.5 * world.mpp
    ts = np.arange(1, int(math.ceil(max_range / step)) + 1) * step
    points = complex(origin) + directions[:, None] * ts[None, :]
    rows, cols, inside = world.to_cells(points.ravel())
    hit = (~inside | world.blocked[rows, cols]).reshape(points.shape)
    first = hit.argmax(axis=1)
    ranges = np.where(hit.any(axis=1), ts[first] - 0.5 * step, max_range)
    if len(people):
        rel = (np.asarray(people, complex) - complex(origin))[None, :] * np.conj(directions)[:, None]
        along, across = rel.real, rel.imag
        r = np.asarray(radii, float)[None, :]
        crosses = (np.abs(across) <= r) & (along + r > 0)
        entry = along - np.sqrt(np.maximum(r * r - across * across, 0.0))
        entry = np.where(crosses, np.maximum(entry, 0.0), np.inf)
        ranges = np.minimum(ranges, entry.min(axis=1))
    return np.clip(ranges, 0.0, max_range).astype(np.float32)


def _descend(field: np.ndarray, row: int, col: int, limit: int) -> list[tuple[int, int]]:
    """Planner cells from (row, col) down the steepest descent of `field` to its minimum (at most `limit` steps)."""
    rows, cols = field.shape
    cells = [(row, col)]
    if not math.isfinite(field[row, col]):  # standing where no disc fits: the best cell around, as robot.planner
        r0, c0 = max(row - 3, 0), max(col - 3, 0)
        block = field[r0:row + 4, c0:col + 4]
        if not np.isfinite(block).any():
            return cells
        dr, dc = np.unravel_index(int(np.argmin(block)), block.shape)
        row, col = r0 + int(dr), c0 + int(dc)
        cells.append((row, col))
    for _ in range(limit):
        r0, c0 = max(row - 1, 0), max(col - 1, 0)
        block = field[r0:row + 2, c0:col + 2]
        dr, dc = np.unravel_index(int(np.argmin(block)), block.shape)
        nr, nc = r0 + int(dr), c0 + int(dc)
        if block[dr, dc] >= field[row, col]:
            break
        row, col = nr, nc
        cells.append((row, col))
    return cells


def _centres(world: World, cells: list[tuple[int, int]], scale: int) -> np.ndarray:
    """World points (complex) of planner cells' centres."""
    rc = np.asarray(cells, float) * scale + 0.5 * (scale - 1)
    xy = world.transform.pixels_to_world(np.stack([rc[:, 1], rc[:, 0]], axis=1))
    return xy[:, 0] + 1j * xy[:, 1]


def resample(polyline: np.ndarray, count: int, spacing: float) -> np.ndarray:
    """`count` points `spacing` m apart along a complex polyline, from `spacing` after its start; its end
    repeated past its length."""
    polyline = np.asarray(polyline, complex)
    if len(polyline) == 1:
        return np.full(count, polyline[0])
    lengths = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(polyline)))])
    at = np.minimum(spacing * np.arange(1, count + 1), lengths[-1])
    return np.interp(at, lengths, polyline.real) + 1j * np.interp(at, lengths, polyline.imag)


def route_ahead(world: World, fields: np.ndarray, scale: int, waypoints: np.ndarray, index: int, position: complex,
                count: int, spacing: float) -> np.ndarray:
    """(count,) complex world points along the planned way from `position` through waypoints[index:] (see the
    module's docstring); `fields`, `scale`: robot.fields.route_fields and field_scale of these waypoints."""
    need = count * spacing
    way, length, here = [complex(position)], 0.0, complex(position)
    for k in range(index, len(waypoints)):
        row, col = world.to_cells(np.array([here]))[:2]
        limit = int(math.ceil((need - length) / (world.mpp * scale))) + 2  # a step moves at least one cell
        cells = _descend(fields[k], int(row[0]) // scale, int(col[0]) // scale, limit)
        if len(cells) > limit:  # cut short: enough way ahead, the waypoint is farther
            way.extend(_centres(world, cells[1:], scale).tolist())
            break
        leg = np.concatenate([_centres(world, cells[1:], scale) if len(cells) > 1 else np.zeros(0, complex),
                              [complex(waypoints[k])]])
        way.extend(leg.tolist())
        length += float(np.abs(np.diff(np.concatenate([[here], leg]))).sum())
        here = complex(waypoints[k])
        if length >= need:
            break
    return resample(np.array(way), count, spacing)
