"""What a bag shows in Foxglove or RViz besides the agents' states: the map as a nav2 OccupancyGrid, the
scene graph and the planned paths as MarkerArrays (once, at the start), and the agents as discs with
their names, gestures and running actions (every step)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from socnavgen.bag.types import header, point, pose
from socnavgen.bt.library import HUMAN_GESTURES, ROBOT_GESTURES
from socnavgen.sim.trace import Trace

if TYPE_CHECKING:
    from rosbags.typesys.store import Typestore

    from socnavgen.location import Location
    from socnavgen.run import PathPlan

ROBOT_COLOUR = (0.85, 0.1, 0.1)
HUMAN_COLOURS = ((0.12, 0.47, 0.71), (1.0, 0.5, 0.05), (0.17, 0.63, 0.17), (0.58, 0.4, 0.74), (0.55, 0.34, 0.29),
                 (0.89, 0.47, 0.76), (0.5, 0.5, 0.5), (0.74, 0.74, 0.13), (0.09, 0.75, 0.81))
MARKER = "visualization_msgs/msg/Marker"
MARKER_ARRAY = "visualization_msgs/msg/MarkerArray"


def human_colour(index: int) -> tuple[float, float, float]:
    return HUMAN_COLOURS[index % len(HUMAN_COLOURS)]


def occupancy_grid(store: Typestore, location: Location, stamp_ns: int) -> Any:
    """The location's occupancy as nav_msgs/OccupancyGrid (100 occupied, 0 free, -1 unknown), placed by the
    location's own transform: the grid's origin is the world pose of the image's lower-left corner and its x
    axis the image's column direction (map_server's convention; any rotation of the map is kept)."""
    grid = location.occupancy
    values = np.where(grid.unknown, -1, np.where(grid.occupied, 100, 0)).astype(np.int8)
    m = location.transform.matrix
    ex, ey = m[:2, 0], m[:2, 1]  # world step of one pixel right, one pixel down
    up_is_left_of_x = float(ex[0] * -ey[1] - ex[1] * -ey[0]) > 0  # -ey is +90 deg from ex: rows run upward
    if up_is_left_of_x:
        values = values[::-1]  # OccupancyGrid row 0 is at the origin: the image's bottom row
        corner = location.transform.pixel_to_world(-0.5, grid.height - 0.5)
    else:
        corner = location.transform.pixel_to_world(-0.5, -0.5)
    yaw = math.atan2(ex[1], ex[0])
    info = store.types["nav_msgs/msg/MapMetaData"](
        map_load_time=header(store, stamp_ns).stamp, resolution=float(location.transform.meters_per_pixel),
        width=grid.width, height=grid.height, origin=pose(store, corner[0], corner[1], yaw))
    return store.types["nav_msgs/msg/OccupancyGrid"](header=header(store, stamp_ns), info=info,
                                                     data=np.ascontiguousarray(values).reshape(-1))


def _colour(store: Typestore, rgb: tuple[float, float, float], alpha: float = 1.0) -> Any:
    return store.types["std_msgs/msg/ColorRGBA"](r=float(rgb[0]), g=float(rgb[1]), b=float(rgb[2]), a=float(alpha))


def _marker(store: Typestore, stamp_ns: int, ns: str, ident: int, kind: int, *, x: float = 0.0, y: float = 0.0,
            yaw: float = 0.0, scale: tuple[float, float, float] = (1.0, 1.0, 1.0),
            rgb: tuple[float, float, float] = (1.0, 1.0, 1.0), alpha: float = 1.0, points: list | None = None,
            text: str = "", z: float = 0.0) -> Any:
    types = store.types
    return types[MARKER](
        header=header(store, stamp_ns), ns=ns, id=ident, type=kind, action=0, pose=pose(store, x, y, yaw, z),
        scale=types["geometry_msgs/msg/Vector3"](x=float(scale[0]), y=float(scale[1]), z=float(scale[2])),
        color=_colour(store, rgb, alpha), lifetime=types["builtin_interfaces/msg/Duration"](sec=0, nanosec=0),
        frame_locked=False, points=points or [], colors=[], texture_resource="",
        texture=types["sensor_msgs/msg/CompressedImage"](header=header(store, 0, ""), format="",
                                                          data=np.zeros(0, np.uint8)),
        uv_coordinates=[], text=text, mesh_resource="",
        mesh_file=types["visualization_msgs/msg/MeshFile"](filename="", data=np.zeros(0, np.uint8)),
        mesh_use_embedded_materials=False)


def scene_graph_markers(store: Typestore, location: Location, stamp_ns: int) -> Any:
    """Nodes as small spheres labelled `id TYPE`, edges as one line list."""
    cls: Any = store.types[MARKER]  # a generated message class: its constants are not typed
    graph = location.scene_graph
    markers = []
    where = {n: location.node_world(n) for n in graph.node_ids()}
    for k, node in enumerate(graph.node_ids()):
        x, y = where[node]
        markers.append(_marker(store, stamp_ns, "scene_graph_nodes", k, cls.SPHERE, x=x, y=y,
                               scale=(0.25, 0.25, 0.25), rgb=(0.2, 0.2, 0.2), alpha=0.8))
        markers.append(_marker(store, stamp_ns, "scene_graph_labels", k, cls.TEXT_VIEW_FACING, x=x, y=y, z=0.4,
                               scale=(0.3, 0.3, 0.3), rgb=(0.1, 0.1, 0.1), text=f"{node} {graph.node(node).type}"))
    lines = [point(store, *where[n]) for a, b in location.graph.edges() for n in (a, b)]
    markers.append(_marker(store, stamp_ns, "scene_graph_edges", 0, cls.LINE_LIST, scale=(0.05, 0.0, 0.0),
                           rgb=(0.4, 0.4, 0.4), alpha=0.6, points=lines))
    return store.types[MARKER_ARRAY](markers=markers)


def path_markers(store: Typestore, location: Location | None, plan: PathPlan | None, trace: Trace,
                 stamp_ns: int) -> Any:
    """The robot's waypoints (red) and each human's planned path (its colour) as line strips; interaction
    points as stars' stand-ins (larger spheres)."""
    cls: Any = store.types[MARKER]  # a generated message class: its constants are not typed
    markers = [_marker(store, stamp_ns, "robot_path", 0, cls.LINE_STRIP, scale=(0.08, 0.0, 0.0), rgb=ROBOT_COLOUR,
                       points=[point(store, x, y, 0.02) for x, y in trace.robot_waypoints])]
    if location is not None and plan is not None:
        for k, name in enumerate(trace.human_names):
            human = next((h for h in plan.humans if h.name == name), None)
            if human is None:
                continue
            pts = [point(store, *location.node_world(n), 0.02) for n in human.path]
            markers.append(_marker(store, stamp_ns, "human_paths", k, cls.LINE_STRIP, scale=(0.05, 0.0, 0.0),
                                   rgb=human_colour(k), alpha=0.8, points=pts))
            if human.interaction_point:
                x, y = location.node_world(human.interaction_point)
                markers.append(_marker(store, stamp_ns, "interaction_points", k, cls.SPHERE, x=x, y=y,
                                       scale=(0.5, 0.5, 0.05), rgb=human_colour(k), alpha=0.5))
    return store.types[MARKER_ARRAY](markers=markers)


def agent_markers(store: Typestore, trace: Trace, k: int, stamp_ns: int) -> Any:
    """Step k: the robot and every human as a disc of its radius, each labelled with its name, the phrase
    it shows and (humans) the action its tree runs."""
    cls: Any = store.types[MARKER]  # a generated message class: its constants are not typed
    markers = []
    rx, ry, ryaw = (float(v) for v in trace.robot[k, :3])
    markers.append(_marker(store, stamp_ns, "robot", 0, cls.CYLINDER, x=rx, y=ry, yaw=ryaw, z=0.25,
                           scale=(2 * trace.robot_radius, 2 * trace.robot_radius, 0.5), rgb=ROBOT_COLOUR))
    said = ROBOT_GESTURES.get(int(trace.robot_gesture[k]), "") if trace.robot_gesture[k] else ""
    markers.append(_marker(store, stamp_ns, "robot_label", 0, cls.TEXT_VIEW_FACING, x=rx, y=ry, z=1.0,
                           scale=(0.3, 0.3, 0.3), rgb=ROBOT_COLOUR, text="robot" + (f": {said}" if said else "")))
    for i, name in enumerate(trace.human_names):
        x, y, yaw = (float(v) for v in trace.humans[k, i, :3])
        r = float(trace.human_radii[i])
        markers.append(_marker(store, stamp_ns, "humans", i, cls.CYLINDER, x=x, y=y, yaw=yaw, z=0.9,
                               scale=(2 * r, 2 * r, 1.8), rgb=human_colour(i), alpha=0.9))
        label = name
        gesture = int(trace.human_gesture[k, i])
        if gesture:
            label += f": {HUMAN_GESTURES.get(gesture, str(gesture))}"
        action = int(trace.action[k, i])
        if 0 <= action < len(trace.node_names):
            label += f" ({trace.node_names[action]})"
        markers.append(_marker(store, stamp_ns, "human_labels", i, cls.TEXT_VIEW_FACING, x=x, y=y, z=2.1,
                               scale=(0.3, 0.3, 0.3), rgb=human_colour(i), text=label))
    return store.types[MARKER_ARRAY](markers=markers)
