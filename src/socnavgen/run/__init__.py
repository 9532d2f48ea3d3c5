"""The run folder: one generated scenario, as plain files every later stage reads."""

from socnavgen.run.folder import RunFolder
from socnavgen.run.models import (
    HumanPlan,
    Manifest,
    PathPlan,
    RobotGestureRule,
    ScenarioProposal,
    ScenarioRequest,
    StageRecord,
)

__all__ = ["HumanPlan", "Manifest", "PathPlan", "RobotGestureRule", "RunFolder", "ScenarioProposal",
           "ScenarioRequest", "StageRecord"]
