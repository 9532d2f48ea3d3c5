"""The behavior-tree node library: ONE table from which the prompt text, the validator, the
simulator's dispatch, the Groot2 model and the exporters' translations are all derived.

Semantics follow ../shared/reference/hunav-node-library.md (SocRATES fork of HuNavSim, BT.CPP v3).
Where the fork's code and the paper disagree, the simulator does what the paper and the prompt
*say* (that is what the model is told); each such choice is written in `sim_note`.
"""

from __future__ import annotations

import math
import re
from enum import StrEnum
from typing import Any, Literal, cast, get_args

from pydantic import BaseModel, Field

from socnavgen.bt.hunav2_facts import HUNAV2 as HUNAV2
from socnavgen.bt.hunav2_facts import HUNAV2_FIRST_AGENT_ID as HUNAV2_FIRST_AGENT_ID
from socnavgen.bt.hunav2_facts import HUNAV2_REGISTERED as HUNAV2_REGISTERED
from socnavgen.bt.hunav2_facts import Hunav2Translation as Hunav2Translation
from socnavgen.bt.hunav2_facts import RegisteredNode as RegisteredNode
from socnavgen.bt.hunav2_facts import RegisteredPort as RegisteredPort


class PortType(StrEnum):
    INT = "int"
    DOUBLE = "double"
    BOOL = "bool"
    STRING = "string"


class Port(BaseModel):
    name: str
    type: PortType
    description: str
    required: bool = True
    default: str | None = None
    # Codes a message port may take (gesture tables); None = any value of the type.
    allowed: dict[int, str] | None = None
    # The root blackboard entry the port must read ({id}: the agent's own id, {dt}: the step), directly
    # or through SubTree remaps and SetBlackboard copies; a literal or any other entry is refused.
    reads_root: Literal["id", "dt"] | None = None
    other_human: bool = False  # holds another human's id (checked against the scenario's humans)
    # A value the prompt shows and the grammar offers besides the type's literals (TimeExpiredCondition's
    # ts: {dt}); ports with `reads_root` always show {id} / {dt}.
    example: str | None = None
    # Bounds of a number literal; doubles are distances, durations and speeds: never negative.
    minimum: float | None = None
    maximum: float | None = None

    def bounds(self) -> tuple[float | None, float | None]:
        low = 0.0 if self.minimum is None and self.type is PortType.DOUBLE else self.minimum
        return low, self.maximum


NodeKind = Literal["action", "condition", "control", "decorator", "builtin", "subtree"]
Flow = Literal["sequence", "fallback"]  # how a control node goes through its children
# What a decorator does with its child's status (BT.CPP v3.8 semantics, docs/behavior-trees.md):
#   invert: SUCCESS <-> FAILURE; force_success / force_failure: the status once the child finished;
#   repeat: tick the child again within the tick while it succeeds, `count` times in all, then SUCCESS;
#   retry: tick it again while it fails, `count` times in all, then FAILURE; keep_running: RUNNING until
#   the child fails. RUNNING always passes through.
DecoratorRule = Literal["invert", "force_success", "force_failure", "repeat", "retry", "keep_running"]
Target = Literal["socrates", "hunav2", "hunav1"]  # THE list of export targets (export.targets registers one
TARGETS: tuple[Target, ...] = get_args(Target)    # class per name; bt check/library and the CLI read it)


class NodeSpec(BaseModel):
    name: str
    kind: NodeKind
    ports: list[Port] = Field(default_factory=list)
    description: str  # what the model is told (prompt) and what the simulator implements
    capability: str | None = None  # one line for the stage-1 "what humans can do" list
    targets: set[Target] = Field(default_factory=lambda: {cast(Target, "socrates")})
    hunav2: str | None = None  # name of the 2.x equivalent node (None = no equivalent)
    hunav1: str | None = None  # name in upstream 1.x (None = not available)
    sim_note: str | None = None  # where our simulator differs from Gazebo/HuNavSim, and why
    in_prompt: bool = True  # listed for the model (built-ins are explained by the tutorial)
    min_children: int = 0
    max_children: int | None = 0
    # control nodes: sequence-like or fallback-like, and reactive (earlier children re-ticked every tick,
    # a child after the one that stopped the pass is halted) or with memory (resume at the RUNNING child)
    flow: Flow | None = None
    reactive: bool = False
    rule: DecoratorRule | None = None  # decorators
    count_port: str | None = None  # repeat / retry: the int port holding the number of attempts
    # leaves: the properties the simulator, the verifier and stage 3 read
    moves: bool = False  # an action that commands the body (a tick's action is the last that moved)
    gate: bool = False  # a condition whose SUCCESS lets an interaction run (verifier expectations)
    interaction: bool = False  # an action that is an interaction with the robot or another human
    # the scenario spec's vocabulary (run/spec.py): triggers a condition detects, reactions an action
    # realizes; stage 1 offers, stage 3 requires and the verifier reads them (TRIGGER_NODES, REACTION_NODES)
    detects: tuple[str, ...] = ()
    realizes: tuple[str, ...] = ()

    def port(self, name: str) -> Port | None:
        return next((p for p in self.ports if p.name == name), None)


HUMAN_GESTURES: dict[int, str] = {0: "NO GESTURE", 1: "WAIT", 2: "PROCEED", 3: "EXCUSE ME"}
ROBOT_GESTURES: dict[int, str] = {0: "NO GESTURE", 1: "WAIT", 2: "PROCEED", 3: "ACKNOWLEDGED", 4: "EXCUSE ME",
                                  5: "FOLLOW ME"}

# Distances the prompt explains, so the model picks sensible numbers.
# centre to centre: robot and person touch at bodies.TOUCH_DISTANCE (0.75 m), so "very close" is 1 m
DISTANCE_WORDS = {1.0: "very close", 1.5: "close", 2.5: "moderate distance", 5.0: "far"}

_AGENT = Port(name="agent_id", type=PortType.INT, description="the agent's own id; always write {id}",
              reads_root="id")
_STEP = Port(name="time_step", type=PortType.DOUBLE, description="simulation step; always write {dt}",
             reads_root="dt")
MAX_REPEAT = 1000  # attempts of Repeat / RetryUntilSuccessful: all happen within one tick
# IsRobotBlocking's cone (the SocRATES fork's 0.5 rad): the robot is "in front of" a person this near their heading.
# One home: the simulator's leaf, the verifier's robot_blocking trigger and the prompts read it from here.
BLOCKING_CONE = 0.5  # rad
BLOCKING_DEGREES = round(math.degrees(BLOCKING_CONE))  # 29


def _dist(meaning: str) -> Port:
    return Port(name="distance", type=PortType.DOUBLE, description=meaning)


def _builtin(name: str, kind: NodeKind, description: str, *, in_prompt: bool = False, hunav2: str | None = None,
             ports: list[Port] | None = None, **fields: Any) -> NodeSpec:
    """A node BT.CPP itself registers: every target runs it under its own name (hunav2: `hunav2` when the
    translation changes it). Controls take one or more children, decorators exactly one, the rest none."""
    children = {"control": (1, None), "decorator": (1, 1)}.get(kind, (0, 0))
    return NodeSpec(name=name, kind=kind, description=description, in_prompt=in_prompt, ports=ports or [],
                    targets=set(TARGETS), hunav2=hunav2 or name, hunav1=name, min_children=children[0],
                    max_children=children[1], **fields)


NODES: list[NodeSpec] = [
    # ---- conditions -------------------------------------------------------------------------
    NodeSpec(name="IsRobotVisible", kind="condition", ports=[_AGENT, _dist("metres")], gate=True,
             detects=("robot_visible", "robot_near"),
             description="SUCCESS when the robot is within `distance` metres and in line of sight of the human "
                         "(not hidden behind a wall).",
             capability="Check whether the robot is visible to the human (within a distance, not behind a wall)",
             targets={"socrates", "hunav2", "hunav1"}, hunav2="IsRobotVisible", hunav1="IsRobotVisible",
             sim_note="The fork has no line-of-sight test and a field of view over 180 deg; we test line of "
                      "sight on the occupancy map, as the prompt says."),
    NodeSpec(name="IsRobotNearby", kind="condition", ports=[_AGENT, _dist("metres")], gate=True,
             detects=("robot_near",),
             description="SUCCESS when the robot is within `distance` metres of the human, walls or not. Each "
                         "human measures from where they stand: in a group, those nearer the robot succeed first "
                         "(to make people go one after the other, time them from one shared cue such as a "
                         "robot phrase).",
             capability="Check whether the robot is near the human",
             targets={"socrates", "hunav2"}, hunav2="IsRobotClose"),
    NodeSpec(name="IsRobotBlocking", kind="condition", ports=[_AGENT, _dist("metres")], gate=True,
             detects=("robot_blocking",),
             description="SUCCESS when the robot is within `distance` metres, in line of sight, and in front of "
                         f"the human (within {BLOCKING_DEGREES} degrees of the way it faces), i.e. in its way. A robot "
                         "standing beside the human's way (waiting for them to pass) is not in front of them.",
             capability="Check whether the robot is blocking the human's path",
             targets={"socrates"},
             sim_note="The fork checks distance and a 0.5 rad cone only; we also require line of sight."),
    NodeSpec(name="IsGoalReached", kind="condition", ports=[_AGENT],
             description="SUCCESS when the human is within its goal radius (+0.1 m) of its current goal.",
             capability="Check whether the human has reached its goal",
             targets={"socrates", "hunav2", "hunav1"}, hunav2="IsGoalReached", hunav1="IsGoalReached"),
    NodeSpec(name="TimeExpiredCondition", kind="condition",
             ports=[Port(name="seconds", type=PortType.DOUBLE, description="duration in seconds", required=False,
                         default="1.0"),
                    Port(name="ts", type=PortType.DOUBLE, description="time added per tick; write {dt}",
                         required=False, default="0.01", example="{dt}"),
                    Port(name="only_once", type=PortType.BOOL, required=False, default="false",
                         description="true: stays SUCCESS once expired; false: the timer restarts")],
             description="Counts the time it is ticked; FAILURE until `seconds` have accumulated, then SUCCESS "
                         "(with only_once=false the count restarts after each SUCCESS). Wrap it in an Inverter "
                         "to do something only for the first `seconds`.",
             capability="Do something only for a limited time, or only after some time has passed",
             detects=("time",),
             targets={"socrates", "hunav1"}, hunav1="TimeExpiredCondition"),
    NodeSpec(name="RobotSays", kind="condition", gate=True,
             detects=("robot_says",),
             ports=[_AGENT, Port(name="message", type=PortType.INT, description="gesture code",
                                 allowed=ROBOT_GESTURES)],
             description="SUCCESS while the robot is making the gesture `message`.",
             capability="React to what the robot says: WAIT, PROCEED, ACKNOWLEDGED, EXCUSE ME, FOLLOW ME",
             targets={"socrates"}),
    NodeSpec(name="HumanSays", kind="condition", gate=True,
             detects=("human_says",),
             ports=[_AGENT, Port(name="target_id", type=PortType.INT, description="id of the other human (0-based)",
                                 other_human=True),
                    Port(name="message", type=PortType.INT, description="gesture code", allowed=HUMAN_GESTURES)],
             description="SUCCESS while human `target_id` is making the gesture `message`.",
             capability="React to a gesture of another human",
             targets={"socrates"}),
    NodeSpec(name="RobotMoved", kind="condition", ports=[_AGENT], gate=True,
             detects=("robot_moving",),
             description="SUCCESS while the robot is moving (speed above 0.1 m/s).",
             capability="Check whether the robot is currently moving",
             targets={"socrates"},
             sim_note="The fork compares signed velocity components, so a robot moving toward -x/-y counts as "
                      "still; we use the speed, as the prompt says."),
    # ---- actions ----------------------------------------------------------------------------
    NodeSpec(name="UpdateGoal", kind="action", ports=[_AGENT],
             description="Move on to the next goal of the human's goal list (the last goal is kept).",
             capability=None, targets={"socrates", "hunav2", "hunav1"}, hunav2="UpdateGoal", hunav1="UpdateGoal"),
    NodeSpec(name="RegularNav", kind="action", ports=[_AGENT, _STEP], moves=True,
             realizes=("walk_past", "join"),
             description="One step of normal social-force walking toward the current goal; the robot is "
                         "treated as an ordinary obstacle.",
             capability="Walk normally to its goal, treating the robot as an ordinary obstacle",
             targets={"socrates", "hunav2", "hunav1"}, hunav2="RegularNav", hunav1="RegularNav",
             sim_note="The fork leaves the robot out of the social force of LLM-tree agents; we include it, "
                      "as the prompt says."),
    NodeSpec(name="MakeGesture", kind="action", interaction=True,
             realizes=("stop", "say", "wait_then_go"),
             ports=[_AGENT, Port(name="message", type=PortType.INT, description="gesture code",
                                 allowed=HUMAN_GESTURES)],
             description="The human makes the gesture `message` and keeps making it until another MakeGesture "
                         "changes it (0 stops). No motion.",
             capability="Say WAIT, PROCEED or EXCUSE ME to the robot",
             targets={"socrates"}, hunav2="SaySomething"),
    NodeSpec(name="LookAtRobot", kind="action", ports=[_AGENT], moves=True, interaction=True,
             realizes=("stop", "look", "wait_then_go"),
             description="The human stops and turns to face the robot.",
             capability="Stop and look at the robot",
             targets={"socrates", "hunav2"}, hunav2="LookAtRobot", hunav1="SurprisedNav"),
    NodeSpec(name="FollowRobot", kind="action", ports=[_AGENT, _STEP], moves=True, interaction=True,
             realizes=("follow",),
             description="One step following the robot; the human walks at their own pace to catch up and stands about "
                         "1.3 m behind it, facing it. From ahead of a robot a `wait` cue holds they come up and stand 1.3 m "
                         "in front of it, facing it (to take something); in its way as it drives, they step aside.",
             capability="Follow the robot",
             targets={"socrates", "hunav2"}, hunav2="ApproachRobot", hunav1="CuriousNav",
             sim_note="HuNavSim's follower (CuriousNav) walks up to the robot even from in front of it and stands "
                      "1.5 m ahead of it, blocking it for good; ours comes up so only while a cue holds the robot and "
                      "steps aside once it drives (GiveWaytoRobot's side step), "
                      "and the hunav2 export walks a follower the robot comes within 2 m of on along its goals "
                      "(AvoidRobot). HuNavSim's follower closes a gap at 0.18 m/s per metre and stops at 1.5 m; ours "
                      "walks at its own pace and stops at 1.3 m (people keep 1-1.5 m behind whom they follow)."),
    NodeSpec(name="FollowHuman", kind="action", moves=True, interaction=True,
             realizes=("follow_human", "join"),
             ports=[_AGENT, Port(name="target_id", type=PortType.INT, description="id of the human to follow",
                                 other_human=True),
                    _STEP],
             description="One step following human `target_id` at the follower's own pace, stopping about 1.3 m "
                         "from them; once they stand at the end of their walk, the follower stands beside them.",
             capability="Follow another human",
             targets={"socrates", "hunav2"}, hunav2="FollowAgent"),
    NodeSpec(name="RunAwayFromRobot", kind="action", ports=[_AGENT, _STEP], moves=True, interaction=True,
             realizes=("avoid",),
             description="One step of scared walking: slow (0.6 m/s) and strongly pushed away from the robot "
                         "while still heading for the goal.",
             capability="Be scared of the robot and avoid it",
             targets={"socrates", "hunav1"}, hunav1="ScaredNav"),
    NodeSpec(name="GiveWaytoRobot", kind="action", ports=[_AGENT, _STEP], moves=True, interaction=True,
             realizes=("give_way",),
             description="One step of giving way: the human steps to the side of the robot's path and stays there "
                         "until the robot has gone by (past them, and where they go back to is out of its way), then "
                         "walks toward its current goal (not on to the next ones), whatever the path's length. A "
                         "give-way once begun goes on inside RegularNav (RunAwayFromRobot: once they stand aside) "
                         "until then: when its gate stops holding (a phrase is shown only a few seconds), fall through "
                         "to walking; a standing branch (MakeGesture, LookAtRobot) stops them where they are, maybe "
                         "still in the robot's way.",
             capability="Give way to the robot (step aside, let it pass)",
             targets={"socrates"},
             sim_note="The fork computes the side step and then discards it (a plain walking step); we "
                      "really step aside, as the prompt says."),
    NodeSpec(name="BlockRobot", kind="action", ports=[_AGENT, _STEP], moves=True, interaction=True,
             realizes=("block",),
             description="One step moving quickly to a point 1.5 m in front of the robot, facing it when close, "
                         "to block its way.",
             capability="Move in front of the robot and block it",
             targets={"socrates", "hunav2", "hunav1"}, hunav2="BlockRobot", hunav1="ThreateningNav"),
    # ---- control flow and built-ins (explained by the BT tutorial; BT.CPP registers them in v3 and v4) --
    _builtin("Sequence", "control", "ticks children in order; fails at the first failure", flow="sequence",
             in_prompt=True, hunav2="ReactiveSequence"),
    _builtin("Fallback", "control", "ticks children in order; succeeds at the first success", flow="fallback",
             in_prompt=True, hunav2="ReactiveFallback"),
    _builtin("ReactiveSequence", "control", "like Sequence, re-checking earlier children every tick",
             flow="sequence", reactive=True),
    _builtin("ReactiveFallback", "control", "like Fallback, re-checking earlier children every tick",
             flow="fallback", reactive=True),
    _builtin("Inverter", "decorator", "turns SUCCESS into FAILURE and back", rule="invert", in_prompt=True),
    _builtin("ForceSuccess", "decorator", "always SUCCESS", rule="force_success"),
    _builtin("ForceFailure", "decorator", "always FAILURE", rule="force_failure"),
    _builtin("Repeat", "decorator", "ticks its child again while it succeeds, `num_cycles` times within the tick",
             rule="repeat", count_port="num_cycles",
             ports=[Port(name="num_cycles", type=PortType.INT, description="how many times", minimum=1,
                         maximum=MAX_REPEAT)]),
    _builtin("RetryUntilSuccessful", "decorator",
             "ticks its child again while it fails, at most `num_attempts` times within the tick",
             rule="retry", count_port="num_attempts",
             ports=[Port(name="num_attempts", type=PortType.INT, description="how many attempts", minimum=1,
                         maximum=MAX_REPEAT)]),
    _builtin("KeepRunningUntilFailure", "decorator",
             "ticks its child, RUNNING while it succeeds (FAILURE when it fails). Right after a condition in a "
             "Sequence it latches: the Sequence resumes at it on later ticks without checking the condition "
             "again, so the action goes on for good once the condition held", rule="keep_running",
             in_prompt=True),
    _builtin("SetBlackboard", "builtin", "writes `value` into the blackboard entry `output_key`", in_prompt=True,
             ports=[Port(name="output_key", type=PortType.STRING, description="blackboard key to write"),
                    Port(name="value", type=PortType.STRING, description="value or {key} to copy")]),
    _builtin("SubTree", "subtree", "runs another BehaviorTree; extra attributes remap its ports to parent keys",
             in_prompt=True,
             ports=[Port(name="ID", type=PortType.STRING, description="id of the BehaviorTree to run")]),
]

# ==== BEGIN latching conditions ================================================================
# Conditions whose SUCCESS, once reached, stays: "once the robot said FOLLOW ME, keep following".
NODES.append(
    NodeSpec(name="RobotSaid", kind="condition",
             detects=("robot_says",),
             ports=[_AGENT, Port(name="message", type=PortType.INT, description="gesture code",
                                 allowed=ROBOT_GESTURES)],
             description="SUCCESS once the robot has made the gesture `message` at any time so far (and from "
                         "then on, even after it stopped); use it for reactions that must last, e.g. keep "
                         "following after the robot said FOLLOW ME.",
             capability="React for good to something the robot said earlier (it said FOLLOW ME once: keep "
                        "following)",
             targets={"socrates"},
             sim_note="Not in the SocRATES fork or HuNavSim (their RobotSays holds only while the gesture is "
                      "shown); the simulator remembers every gesture the robot has shown."))
# ==== END latching conditions ===================================================================

LIBRARY: dict[str, NodeSpec] = {n.name: n for n in NODES}

# Entries every agent's root blackboard holds (HuNavSim sets them before each tick).
ROOT_KEYS: dict[str, PortType] = {"id": PortType.INT, "dt": PortType.DOUBLE}

# Trees the library ships and that a generated tree may `include` (file name -> main tree id).
LIBRARY_TREES: dict[str, str] = {"BTRegularNav.xml": "RegularNavTree"}

REGULAR_NAV_XML = """<root main_tree_to_execute="RegularNavTree">
    <BehaviorTree ID="RegularNavTree">
        <Fallback name="RegularNavFallback">
            <Sequence name="RegularNavigation">
                <Inverter>
                    <IsGoalReached agent_id="{id}"/>
                </Inverter>
                <RegularNav agent_id="{id}" time_step="{dt}"/>
            </Sequence>
            <UpdateGoal agent_id="{id}"/>
        </Fallback>
    </BehaviorTree>
</root>
"""

LIBRARY_TREE_XML: dict[str, str] = {"BTRegularNav.xml": REGULAR_NAV_XML}

# How a tree walks normally: copy `id` and `dt` into the keys the RegularNavTree subtree's ports are
# remapped to (BT.CPP subtrees have isolated blackboards).
REGULAR_NAV_CALL: tuple[str, ...] = (
    '<SetBlackboard output_key="agentid" value="{id}"/>',
    '<SetBlackboard output_key="timestep" value="{dt}"/>',
    '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>',
)


def regular_nav_sequence(pad: str = "", name: str = "WalkPath") -> str:
    """The walking idiom as an indented `<Sequence>` block."""
    inner = "\n".join(pad + "    " + line for line in REGULAR_NAV_CALL)
    return f'{pad}<Sequence name="{name}">\n{inner}\n{pad}</Sequence>\n'


def regular_walker_xml(tree_id: str = "MainTree") -> str:
    """A complete tree that only walks its path (what a human without a generated tree does)."""
    return (f'<root main_tree_to_execute="{tree_id}">\n  <include path="BTRegularNav.xml"/>\n'
            f'  <BehaviorTree ID="{tree_id}">\n{regular_nav_sequence("    ")}  </BehaviorTree>\n</root>\n')


def known_nodes(target: Target | None = None) -> dict[str, NodeSpec]:
    """The nodes a tree may name: every library node (what the simulator runs), or those `target`'s loader
    knows; HuNavSim 2.x's own nodes are unknown to the v3 node libraries of socrates and hunav1. A known
    node the target cannot run is named as such by `bt check --target`."""
    if target is None or target == "hunav2":
        return dict(LIBRARY)
    return {name: spec for name, spec in LIBRARY.items() if spec.targets != {"hunav2"}}


def leaf_nodes() -> list[NodeSpec]:
    return [n for n in NODES if n.kind in ("action", "condition")]


def prompt_nodes() -> list[NodeSpec]:
    return [n for n in NODES if n.in_prompt]


def hunav2_refusal(name: str) -> str | None:
    """Why `name` cannot be exported to HuNavSim 2.x (None = it can)."""
    tr = HUNAV2.get(name)
    return tr.refusal if tr is not None else None


# 2.x nodes our translations emit, simulated by socnavgen.sim.people.leaves_hunav2 (so a hunav2 export can be
# simulated and verified like its socrates original). Their ports come from HUNAV2_REGISTERED.
HUNAV2_SIMULATED = ("IsRobotClose", "SaySomething", "SurprisedNav", "CuriousNav", "FollowAgent", "AvoidRobot",
                    "ThreateningNav")
_PORT_TYPES = {"int": PortType.INT, "double": PortType.DOUBLE, "bool": PortType.BOOL, "std::string": PortType.STRING}


_ROOT_PORTS: dict[str, Literal["id", "dt"]] = {"agent_id": "id", "time_step": "dt"}


def registered_spec(node: RegisteredNode) -> NodeSpec:
    """A node HuNavSim 2.x registers, as a library row: its declared input ports (one the 2.x code reads
    without a default is required: the tick throws without it); navigation steps (the nodes with a
    time_step) move the person."""
    ports = [Port(name=p.name, type=_PORT_TYPES[p.type], description=f"HuNavSim 2.x port ({p.type})",
                  required=p.read and p.default is None, default=p.default, reads_root=_ROOT_PORTS.get(p.name))
             for p in node.ports if p.direction == "input"]
    if node.kind == "Decorator":
        return NodeSpec(name=node.id, kind="decorator", ports=ports, min_children=1, max_children=1,
                        description=f"HuNavSim 2.x decorator {node.id}", targets={"hunav2"}, in_prompt=False)
    return NodeSpec(name=node.id, kind="action" if node.kind == "Action" else "condition", ports=ports,
                    moves=any(p.name == "time_step" for p in ports),
                    description=f"HuNavSim 2.x {node.kind.lower()} {node.id} (only in hunav2 exports; "
                                "semantics in socnavgen.sim.people.leaves_hunav2)",
                    targets={"hunav2"}, hunav2=node.id, in_prompt=False)


NATIVE_HUNAV2 = [registered_spec(HUNAV2_REGISTERED[n]) for n in HUNAV2_SIMULATED] + [
    NodeSpec(name="AlwaysSuccess", kind="action", description="BT.CPP 4 built-in: SUCCESS, does nothing",
             targets={"hunav2"}, hunav2="AlwaysSuccess", in_prompt=False)]
NODES.extend(NATIVE_HUNAV2)
LIBRARY.update({n.name: n for n in NATIVE_HUNAV2})




def _apply_hunav2_support() -> None:
    """Leaf support for hunav2 comes from HUNAV2 alone (one home): a template = supported, and the
    node's `hunav2` name is the template's outer element."""
    for spec in leaf_nodes():
        if spec.targets == {"hunav2"}:
            continue  # a 2.x node itself
        tr = HUNAV2.get(spec.name)
        if tr is not None and tr.template:
            spec.targets.add("hunav2")
            names = re.findall(r"<(\w+)", tr.template)
            spec.hunav2 = names[0] if len(names) == 1 else "+".join(names[1:])
        elif tr is not None and tr.by_script:
            spec.targets.add("hunav2")
            spec.hunav2 = "the script's condition"
        else:
            spec.targets.discard("hunav2")
            spec.hunav2 = None


_apply_hunav2_support()


def hunav2_text(name: str) -> str:
    """One line for `bt library`, `bt check --target hunav2` and the docs: the 2.x translation and why it
    behaves the same, or the refusal and why (empty for built-ins, which keep their names)."""
    tr = HUNAV2.get(name)
    if tr is None:
        return ""
    if tr.by_script:
        return f"the robot script's condition: {tr.reason}"
    if tr.template is None:
        return f"refused: {tr.refusal}"
    return f"{LIBRARY[name].hunav2 if name in LIBRARY else name}: {tr.reason}"


# ==== BEGIN encounter needs ==================================================================
# What a tree must contain for each part of an encounter of the scenario spec (run/spec.py): the
# conditions that DETECT a human's trigger, and the actions that REALIZE its reaction (the rows'
# `detects` / `realizes`, in library order). Stage 3 checks every tree against them, prompts quote
# them, stage 1 refuses parts a target cannot run. `always` needs no condition.
# `PART_PORTS` says which port of the node must carry which value of the spec part:
#   robot_phrase -> the robot's gesture code of `phrase`; human_phrase -> the human gesture code of
#   `phrase` (or of `says` for the reaction say); other -> the agent id of `other`.
def _encounter_table(field: Literal["detects", "realizes"]) -> dict[str, tuple[str, ...]]:
    table: dict[str, tuple[str, ...]] = {}
    for spec in NODES:
        for key in getattr(spec, field):
            table[key] = (*table.get(key, ()), spec.name)
    return table


TRIGGER_NODES: dict[str, tuple[str, ...]] = {"always": (), **_encounter_table("detects")}
REACTION_NODES: dict[str, tuple[str, ...]] = _encounter_table("realizes")
PART_PORTS: dict[tuple[str, str], dict[str, str]] = {
    ("trigger", "robot_says"): {"message": "robot_phrase"},
    ("trigger", "human_says"): {"message": "human_phrase", "target_id": "other"},
    ("reaction", "say"): {"message": "human_phrase"},
    ("reaction", "follow_human"): {"target_id": "other"},
}


def nodes_for_trigger(trigger: str, target: Target = "socrates") -> list[str]:
    """Library nodes (of `target`) that detect a spec trigger; [] for `always` or when none runs there."""
    return [n.name for n in NODES if trigger in n.detects and target in n.targets]


def nodes_for_reaction(reaction: str, target: Target = "socrates") -> list[str]:
    """Library nodes (of `target`) that realize a spec reaction."""
    return [n.name for n in NODES if reaction in n.realizes and target in n.targets]
# ==== END encounter needs ======================================================================
