"""The run folder: one generated scenario, as plain files every later stage reads."""

from socnavgen.run.folder import RunFolder
from socnavgen.run.loaded import LoadedRun, load_run
from socnavgen.run.models import (
    HumanPlan,
    Manifest,
    PathPlan,
    RobotGestureRule,
    ScenarioProposal,
    ScenarioRequest,
    StageRecord,
)
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotCue, RobotScript, ScenarioSpec

__all__ = ["Criterion", "Encounter", "HumanPart", "RobotCue", "RobotScript", "ScenarioSpec", "HumanPlan", "LoadedRun", "Manifest", "PathPlan", "RobotGestureRule", "RunFolder", "ScenarioProposal",
           "ScenarioRequest", "StageRecord", "load_run"]
