"""HuNavSim 2.x facts, from its public sources (robotics-upo/hunav_sim: the agent manager's
registerBTNodes, the node headers and bt_functions): which nodes 2.x registers with which ports, and
how each node of our library becomes 2.x XML (or why it cannot). Data only; bt.library turns it into
node support, `bt library` text and the 2.x node specs the simulator runs."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field


# ---- HuNavSim 2.x facts (robotics-upo/hunav_sim, agent manager's registerBTNodes and node headers) ---
class RegisteredPort(BaseModel):
    """A port as HuNavSim 2.x declares it. `default` None = no default: the node throws at tick if the
    XML does not set it (BT.CPP 4 ignores defaults written in TreeNodesModel.xml for leaf nodes)."""

    name: str
    type: str  # C++ type as BT.CPP prints it: int, double, bool, std::string
    default: str | None = None
    direction: Literal["input", "output"] = "input"
    read: bool = True  # False: declared but never read by the 2.x code (may be left out of the XML)


class RegisteredNode(BaseModel):
    """A leaf HuNavSim 2.x registers. `stateful` nodes return RUNNING (BT::StatefulActionNode); the rest
    are simple nodes that finish in the tick."""

    id: str
    kind: Literal["Action", "Condition", "Decorator"]
    ports: list[RegisteredPort]
    stateful: bool = False


def _rp(spec: str) -> list[RegisteredPort]:
    """'agent_id:int, threshold:double=1.0, >target:int, ?x:double' -> ports (> output, ? never read)."""
    ports = []
    for item in filter(None, (x.strip() for x in spec.split(","))):
        out, unread = item.startswith(">"), item.startswith("?")
        name, _, rest = item.lstrip(">?").partition(":")
        type_, _, default = rest.partition("=")
        ports.append(RegisteredPort(name=name, type=type_, default=default or None,
                                    direction="output" if out else "input", read=not unread))
    return ports


_NAV = "agent_id:int, time_step:double"
HUNAV2_REGISTERED: dict[str, RegisteredNode] = {n.id: n for n in [
    RegisteredNode(id="TimeExpiredCondition", kind="Condition",
                   ports=_rp("seconds:double=1.0, ts:double=0.01, only_once:bool=false")),
    RegisteredNode(id="IsRobotVisible", kind="Condition", ports=_rp("agent_id:int, distance:double")),
    RegisteredNode(id="IsGoalReached", kind="Condition", ports=_rp("agent_id:int")),
    RegisteredNode(id="RandomChanceCondition", kind="Condition", ports=_rp("probability:double=0.3")),
    RegisteredNode(id="IsRobotFacingAgent", kind="Condition", ports=_rp("agent_id:int")),
    RegisteredNode(id="IsAgentVisible", kind="Condition",
                   ports=_rp("observer_id:int, agent_id:int, distance:double, field_of_view:double")),
    RegisteredNode(id="IsRobotClose", kind="Condition", ports=_rp("agent_id:int, threshold:double=1.0")),
    RegisteredNode(id="IsAtPosition", kind="Condition",
                   ports=_rp("agent_id:int, goal_id:int, tolerance:double=0.1")),
    RegisteredNode(id="IsAgentClose", kind="Condition",
                   ports=_rp("observer_id:int, target_agent_id:int, threshold:double=1.0")),
    RegisteredNode(id="UpdateGoal", kind="Action", ports=_rp("agent_id:int")),
    RegisteredNode(id="RegularNav", kind="Action", ports=_rp(_NAV)),
    RegisteredNode(id="SurprisedNav", kind="Action",
                   ports=_rp("agent_id:int, ?time_step:double, ?beh_duration:double, ?only_once:bool")),
    RegisteredNode(id="CuriousNav", kind="Action", ports=_rp(
        _NAV + ", ?beh_duration:double, ?only_once:bool, agent_vel:double, stop_distance:double")),
    # ScaredNav's code also reads `safe_distance`, which it does not declare: it throws at every tick
    RegisteredNode(id="ScaredNav", kind="Action", ports=_rp(
        _NAV + ", ?beh_duration:double, ?only_once:bool, runaway_vel:double, ?scary_force_factor:double")),
    RegisteredNode(id="ThreateningNav", kind="Action",
                   ports=_rp(_NAV + ", ?beh_duration:double, ?only_once:bool, goal_dist:double")),
    RegisteredNode(id="FindNearestAgent", kind="Action", ports=_rp("agent_id:int, >target_agent_id:int")),
    RegisteredNode(id="SaySomething", kind="Action", ports=_rp("agent_id:int, message:std::string")),
    RegisteredNode(id="SetGroupId", kind="Action", ports=_rp("agent_id:int, group_id:int")),
    RegisteredNode(id="SetGoal", kind="Action",
                   ports=_rp("agent_id:int, ?target_x:double, ?target_y:double, goal_id:int")),
    RegisteredNode(id="StopMovement", kind="Action", ports=_rp("agent_id:int")),
    RegisteredNode(id="ResumeMovement", kind="Action", ports=_rp("agent_id:int")),
    RegisteredNode(id="StopAndWaitTimerAction", kind="Action", stateful=True,
                   ports=_rp("agent_id:int, wait_duration:double=5.0")),
    RegisteredNode(id="ApproachRobot", kind="Action", stateful=True, ports=_rp(
        _NAV + ", closest_dist:double, max_vel:double, duration:double=0.0")),
    RegisteredNode(id="AvoidRobot", kind="Action", stateful=True, ports=_rp(
        _NAV + ", safe_distance:double, runaway_vel:double, duration:double=0.0")),
    RegisteredNode(id="BlockRobot", kind="Action", stateful=True,
                   ports=_rp(_NAV + ", front_dist:double, duration:double=0.0")),
    RegisteredNode(id="FollowAgent", kind="Action", stateful=True, ports=_rp(
        "agent_id:int, target_agent_id:int, time_step:double, closest_dist:double, max_vel:double, "
        "duration:double")),
    RegisteredNode(id="LookAtRobot", kind="Action", stateful=True,
                   ports=_rp("agent_id:int, yaw_tolerance:double=0.01")),
    RegisteredNode(id="TimeDelay", kind="Decorator", ports=_rp("delay:double=1.0")),
]}

HUNAV2_FIRST_AGENT_ID = 1  # HuNavSim 1.x and 2.x number agents from 1 (the SocRATES fork from 0)


class Hunav2Translation(BaseModel):
    """How one library node becomes HuNavSim 2.x XML, and why that is the same behaviour.

    `template` is one v4 element (or a composition) with `{port}` placeholders filled from the node's
    own ports (`{{id}}` writes a literal `{id}`); `by_value` picks another template for particular
    literal values of a port. `refusal` (no template) says why 2.x cannot express the node.
    Control nodes and built-ins are not listed: each library row's `hunav2` names what it becomes
    (Sequence/Fallback their reactive forms, the others keep their names)."""

    template: str | None = None
    by_value: dict[str, dict[str, str]] = Field(default_factory=dict)
    reason: str
    refusal: str | None = None
    by_script: bool = False  # no template: the export writes the robot script's condition (export.speech)
    target_ports: tuple[str, ...] = ()  # ports holding an agent id (shifted to 2.x's 1-based ids)


HUNAV2: dict[str, Hunav2Translation] = {
    "IsRobotVisible": Hunav2Translation(
        template='<IsRobotVisible agent_id="{agent_id}" distance="{distance}"/>',
        reason="2.x keeps the node and its ports"),
    "IsRobotNearby": Hunav2Translation(
        template='<IsRobotClose agent_id="{agent_id}" threshold="{distance}"/>',
        reason="IsRobotClose is the distance-only test (robot closer than `threshold`)"),
    "IsRobotBlocking": Hunav2Translation(
        template='<IsRobotVisible agent_id="{agent_id}" distance="{distance}"/>',
        reason="approximated: 2.x has no condition on where the robot is relative to the person's heading, so "
               "the person reacts to the robot within `distance` in view (2.x IsRobotVisible: a ~200 deg field of "
               "view, not the 30 deg cone); a person who stops for it keeps standing while the robot is that close "
               "(IsRobotVisible + IsRobotFacingAgent, the closest composition, let a stopped person walk on into a "
               "robot driving around it)"),
    "IsGoalReached": Hunav2Translation(template='<IsGoalReached agent_id="{agent_id}"/>',
                                       reason="same node and port in 2.x"),
    "TimeExpiredCondition": Hunav2Translation(
        template='<TimeExpiredCondition seconds="{seconds}" ts="{ts}" only_once="{only_once}"/>',
        reason="2.x registers TimeExpiredCondition with the same ports, defaults and accumulator"),
    "RobotSays": Hunav2Translation(
        by_script=True,
        reason="approximated: HuNavSim 2.x has no input for what the robot says, so the export writes the condition "
               "under which the robot's script says the phrase (blocked / at an encounter: the robot within the "
               "cue's distance, in view, IsRobotVisible; near a person: IsRobotClose; start / after: the time "
               "window, TimeExpiredCondition), without the seconds the phrase is held; a phrase said to another "
               "person or at a place this person does not pass is not heard; refused when the script says it "
               "when a person speaks (2.x cannot tell which phrase)"),
    "RobotSaid": Hunav2Translation(
        by_script=True,
        reason="approximated as RobotSays (the script's condition), latched: once it held, the tree runs with "
               "RobotSaid true for good"),
    "HumanSays": Hunav2Translation(
        reason="", refusal="2.x conditions tell whether another agent is speaking (IsSpeaking), not which "
                           "message it says; HumanSays tests the gesture code"),
    "RobotMoved": Hunav2Translation(
        reason="", refusal="no 2.x condition reads the robot's velocity (IsRobotFacingAgent reads its "
                           "heading, IsRobotClose/IsRobotVisible its position)"),
    "UpdateGoal": Hunav2Translation(template='<UpdateGoal agent_id="{agent_id}"/>', reason="same node in 2.x"),
    "RegularNav": Hunav2Translation(template='<RegularNav agent_id="{agent_id}" time_step="{time_step}"/>',
                                    reason="same node in 2.x (one social-force step)"),
    "MakeGesture": Hunav2Translation(
        template='<SaySomething agent_id="{agent_id}" message="{message_word}"/>',
        by_value={"message": {"0": "<AlwaysSuccess/>"}},
        reason="SaySomething publishes the gesture's word; gesture 0 (stop gesturing) says nothing and, "
               "like MakeGesture, succeeds without moving"),
    "LookAtRobot": Hunav2Translation(
        template='<SurprisedNav agent_id="{agent_id}" beh_duration="0.0" only_once="false"/>',
        reason="SurprisedNav is 2.x's one-step turn toward the robot that finishes in the tick, as ours "
               "does; 2.x's LookAtRobot stays RUNNING until aligned, which would stop re-checking the gate"),
    # (SurprisedNav declares time_step but never reads it: left out, LookAtRobot has no {dt} to pass)
    "FollowRobot": Hunav2Translation(
        template='<ReactiveFallback><ReactiveSequence><IsRobotClose agent_id="{agent_id}" threshold="2.0"/>'
                 '<AvoidRobot agent_id="{agent_id}" time_step="{time_step}" safe_distance="2.0" runaway_vel="0.6" '
                 'duration="0.0"/></ReactiveSequence><CuriousNav agent_id="{agent_id}" time_step="{time_step}" '
                 'beh_duration="0.0" only_once="false" agent_vel="0.8" stop_distance="1.5"/></ReactiveFallback>',
        reason="approximated: CuriousNav is one synchronous follow step that stops 1.5 m from the robot and faces "
               "it (ApproachRobot calls the same function but is stateful, RUNNING forever with duration 0, throws "
               "without max_vel); 2.x has no follow-behind, so a follower the robot comes within 2 m of (one "
               "ahead of it, in its way) walks on along its own goals pushed out of the robot's way (AvoidRobot), "
               "as ours steps aside and lets it pass, instead of standing in front of it"),
    "FollowHuman": Hunav2Translation(
        template='<FollowAgent agent_id="{agent_id}" target_agent_id="{target_id}" time_step="{time_step}" '
                 'closest_dist="1.5" max_vel="1.5" duration="0.0"/>',
        target_ports=("target_id",),
        reason="FollowAgent follows the other agent and stops 1.5 m from it; it is stateful, so the tree's "
               "controls become reactive and re-check every gate each tick, halting it when one fails"),
    "RunAwayFromRobot": Hunav2Translation(
        template='<AvoidRobot agent_id="{agent_id}" time_step="{time_step}" safe_distance="3.0" '
                 'runaway_vel="0.6" duration="0.0"/>',
        reason="AvoidRobot walks on at 0.6 m/s pushed away from the robot; 2.x's ScaredNav reads a port it "
               "does not declare (safe_distance) and throws. Stateful: reactive controls halt it"),
    "GiveWaytoRobot": Hunav2Translation(
        template='<AvoidRobot agent_id="{agent_id}" time_step="{time_step}" safe_distance="2.0" '
                 'runaway_vel="0.6" duration="0.0"/>',
        reason="2.x has no side-step; AvoidRobot keeps the human heading for its goal, slowly (0.6 m/s), pushed "
               "out of the robot's way from 2.0 m (the push outweighs the slow walk, so a person whose goal lies "
               "beyond the robot backs off instead of pressing on). Stateful: reactive controls halt it"),
    "BlockRobot": Hunav2Translation(
        template='<ThreateningNav agent_id="{agent_id}" time_step="{time_step}" beh_duration="0.0" '
                 'only_once="false" goal_dist="1.5"/>',
        reason="ThreateningNav is one synchronous step toward a point in front of the robot (goal_dist "
               "1.5 m, as ours); 2.x's stateful BlockRobot calls the same function but stays RUNNING"),
}
