"""What every export target needs, computed once from a run folder: world poses of humans and
robot, their trees, and the files a target writes (kept in memory until all are ready)."""

from __future__ import annotations

from pydantic import BaseModel, Field

from socnavgen.bt.library import TARGETS, Target
from socnavgen.run.models import PathPlan
from socnavgen.run.spec import ScenarioSpec

ExportFormat = Target  # the names of export.targets' registry (spelled once, in bt.library)
FORMATS: tuple[ExportFormat, ...] = TARGETS

# HuNavSim agent constants (reference §8.1, §9.3): what SocRATES writes for every human.
HUMAN_Z = 1.25  # Gazebo actor height; HuNavSim overrides it per skin but expects it present
SKIN_COUNT = 9  # Gazebo actor meshes 0..8


class WorldPoint(BaseModel):
    """A scene-graph node in metres (map frame) with a heading in radians."""

    node: str
    x: float
    y: float
    yaw: float = 0.0


class HumanExport(BaseModel):
    """One human as HuNavSim spawns it: near the first node of its path, where `simulate` spawns it (same seed),
    facing its first goal."""

    name: str  # human1, human2, ...
    agent_id: int  # 0-based, as SocRATES (human1 -> 0)
    group_id: int = -1
    skin: int
    start: WorldPoint
    goals: list[WorldPoint]
    path: list[str]
    interaction_point: str | None = None
    tree_xml: str
    tree_file: str  # where the tree came from, for messages (behaviors/human1.xml)


class RobotExport(BaseModel):
    start: WorldPoint
    waypoints: list[WorldPoint]
    path: list[str]


class ExportScene(BaseModel):
    """Everything the exporters read; built by `scene.build_scene`, never by pixel math elsewhere."""

    run_name: str
    location_name: str
    humans: list[HumanExport]
    robot: RobotExport
    plan: PathPlan
    spec: ScenarioSpec | None = None  # spec.json (the robot's script, the encounters), None for runs without one
    nodes: dict[str, tuple[float, float]] = Field(default_factory=dict)  # scene-graph node -> world point
    # node of the robot's path -> m before the robot reaches it that a person meeting it there is at it (a door on
    # the robot's way: sim.people.pacing.door_lead; nodes without a lead are left out)
    leads: dict[str, float] = Field(default_factory=dict)
    # node of the robot's path -> its next node, where the leg between them goes through a door within the lead of
    # the node (an elevator's door past its lobby): a person coming from there meets the robot face to face in it
    doors_after: dict[str, str] = Field(default_factory=dict)

    @property
    def robot_speed(self) -> float:
        """The robot's nominal cruise speed (m/s): its script's, else the script's default."""
        from socnavgen.run.spec import RobotScript

        return self.spec.script.speed if self.spec is not None else RobotScript().speed


class ExportedFile(BaseModel):
    """One output file, relative to the output folder."""

    path: str
    text: str


class ExportResult(BaseModel):
    format: ExportFormat
    out_dir: str
    files: list[str] = Field(default_factory=list)
    kept: list[str] = Field(default_factory=list, description="files in the folder no export wrote: left alone")
    removed: list[str] = Field(default_factory=list, description="files of the earlier export it no longer has")
    verification: str = Field(default="never", description="passed | failed | never | stale | unreadable")
    verification_message: str = ""
