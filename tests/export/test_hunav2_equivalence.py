"""A run simulated from its socrates trees and from their hunav2 translation (2.x nodes simulated by
sim.people.leaves_hunav2) gets the same verification outcome, finding by finding, on every card of every
bundled location whose trees translate."""

from __future__ import annotations

from pathlib import Path

from socnavgen.export.as_target import relabel, stands_for

from .conformance_helpers import card_scenes
from .equivalence_helpers import outcomes

# Where 2.x lacks the behaviour, the outcome may differ; each case is named with why (docs/export.md). The
# test fails if another card diverges or if this one stops diverging (then remove it here).
# Since contact is a gap of 5 cm or less (issue 25), whether a person brushes the robot (the simulator puts people
# who walk into it back on its surface, 5 mm away) depends on small differences between the twins' motion.
# Since people step around the robot and it makes way (issue 25), the twins touch nobody; what is left is the
# home hallway (1.2 m, a dead end at 3y), where AvoidRobot keeps 2 m and the robot has no room to pass.
_HALLWAY = ("2.x has no side step: the hunav2 person (AvoidRobot) retreats along the 1.2 m home hallway ahead of the "
            "robot, which never reaches its goal 3y; the socrates person steps aside (GiveWaytoRobot)")
# Measured 2026-11-26 on the merged simulator (people give way with no room, the robot makes way backwards, pacing
# from the robot's live ETA, a robot stopped short of someone at its goal has arrived). The robot-crowding twins no
# longer diverge (both twins of each verify alike) and left this list.
_OVERTAKE = ("2.x has no side step: the overtaken hunav2 person (AvoidRobot) walks on ahead of the robot along the "
             "hospital corridor, out of its way only at its goal (the robot stops short of them at 44 s, 29 s with the "
             "socrates twin, who steps aside at once)")
KNOWN_DIVERGENT = {
    # since side steps are never planned through the robot's body (2026-11-26): the socrates and the 2.x runs of the
    # three followers swarming the robot in the 1.2 m hallway no longer end the same; not analysed finding by finding
    # (home/robot-crowding's twins verify alike since people walk round a robot standing on a point of their way, s11)
    "home/robot-overtaking": _HALLWAY,
    # home/pedestrian-obstruction's twins verify alike again since the eighth session (2026-11-27)
    # since people walk round a robot standing on a point of their way (s11; traced, not seen in a GIF): in the
    # socrates twin the person gives way, the 2.x twin has no side step
    "home/narrow-doorway": "2.x has no side step: the socrates person gives way, the hunav2 one does not",
    # thirteenth session: home/robot-crowding and the three accompanying-peer twins verify alike (told by the
    # verdicts, not traced to one change: a robot getting nowhere for 2 s now counts as idle, so it can arrive short
    # of a 2.x follower hovering at its goal; a follower walking up to a driving robot steps aside again)
    "hospital/robot-overtaking": _OVERTAKE,
    # since people stop short of a goal the robot is on (2026-11-26, s7): the hospital door's twins now verify alike
    # (the card fails in both: tests/cards KNOWN_FAILING) and the hospital hallway's part (finding by finding, not yet
    # looked at in frames): the hunav2 person (AvoidRobot) never leaves the robot's way, the robot stands behind them
    # over 10 s and never reaches 0g; the socrates person gives way after EXCUSE ME and the robot passes
    "hospital/narrow-hallway": "2.x has no side step: the hunav2 person stays in the robot's way in the hallway",
    # eighth session (2026-11-27: the default robot brakes within 1.5 m/s2, goes round a group standing on its
    # waypoint, stops short of someone standing; followers queue; told by the verdicts, not looked at in frames)
    # (warehouse/pedestrian-obstruction's twins verify alike again since the fifteenth session: told by the verdicts)
    # (warehouse/robot-crowding's twins verify alike since the sixteenth session, and home/robot-crowding's do not:
    # a point on a person's way that another reached first is walked through, not stood round; told by the verdicts)
    "home/robot-crowding": "the socrates and the 2.x crowds of followers round the robot in the 1.2 m hallway end "
    "differently (the socrates twin touches the plain waypoint robot: test_as_target KNOWN_LOST); not analysed "
    "finding by finding",
}


def test_socrates_and_hunav2_runs_verify_the_same(tmp_path_factory) -> None:  # noqa: ANN001
    work = Path(tmp_path_factory.mktemp("equivalence"))
    scenes = card_scenes(str(work / "cards"))
    compared, refused, different = 0, 0, []
    for label, scene in scenes:
        run_dir = work / "cards" / label.replace("/", "__")
        result = outcomes(run_dir, scene, work / "twins" / label.replace("/", "__"))
        if result is None:
            refused += 1
            continue
        compared += 1
        socrates, hunav2 = result
        if socrates != hunav2:
            different.append((label, {k: (socrates.get(k), hunav2.get(k)) for k in socrates.keys() | hunav2.keys()
                                      if socrates.get(k) != hunav2.get(k)}))
    assert {label for label, _ in different} == set(KNOWN_DIVERGENT), different
    assert compared >= 40 and compared > 4 * refused, (compared, refused)


def test_relabel_moves_actions_and_successes_to_the_library_node() -> None:
    import numpy as np

    from socnavgen.sim.engine.simulation import NODE_NAMES
    from socnavgen.sim.trace import Trace

    tree = ("<root main_tree_to_execute='T'><BehaviorTree ID='T'><Sequence><IsRobotNearby agent_id='{id}' "
            "distance='2'/><FollowRobot agent_id='{id}' time_step='{dt}'/></Sequence></BehaviorTree></root>")
    mapping = stands_for(tree)
    # FollowRobot is a composition: both of its 2.x actions stand for it (its IsRobotClose gate does not)
    assert mapping == {"IsRobotClose": "IsRobotNearby", "CuriousNav": "FollowRobot", "AvoidRobot": "FollowRobot"}
    curious, follow = NODE_NAMES.index("CuriousNav"), NODE_NAMES.index("FollowRobot")
    close, nearby = NODE_NAMES.index("IsRobotClose"), NODE_NAMES.index("IsRobotNearby")
    trace = Trace.__new__(Trace)
    trace.node_names = NODE_NAMES
    trace.action = np.array([[curious], [-1]], dtype=np.int16)
    trace.succeeded = np.array([[1 << close], [0]], dtype=np.int64)
    out = relabel(trace, [mapping])
    assert out.action[:, 0].tolist() == [follow, -1]
    assert out.succeeded[0, 0] >> nearby & 1 and not out.succeeded[1, 0]


REACTIONS = {
    "RunAwayFromRobot": '<IsRobotNearby agent_id="{id}" distance="4.0"/>'
                        '<RunAwayFromRobot agent_id="{id}" time_step="{dt}"/>',
    "BlockRobot": '<IsRobotVisible agent_id="{id}" distance="6.0"/><BlockRobot agent_id="{id}" time_step="{dt}"/>',
    "GiveWaytoRobot": '<IsRobotNearby agent_id="{id}" distance="3.0"/>'
                      '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/>',
}

# (node, finding) -> why it differs (the test fails if it stops differing). Measured 2026-11-26 on the merged simulator:
# paced from the robot's live ETA, human1 now walks to `up` at its own speed to arrive WITH the robot, so the 3 m
# trigger fires with both ~1.5 m from the node
REACTIONS_DIVERGENT: dict[tuple[str, str], str] = {
    # GiveWaytoRobot's twins meet the robot alike again since the eighth session (2026-11-27; the robot brakes within
    # 1.5 m/s2 and stops short of someone standing in its way): before, the socrates person stepped aside 2.3 m before
    # up and the two were closest 2.08 m from the node while the hunav2 one met the robot 0.53 m from it
}


def test_reactions_no_card_uses_verify_the_same(tmp_path: Path) -> None:
    """Translations the cards do not exercise, on a head-on encounter (warehouse frontal-approach)."""
    import shutil

    from socnavgen.bt.library import regular_nav_sequence
    from socnavgen.cards.generate import write_card_run
    from socnavgen.export.scene import build_scene
    from socnavgen.run import RunFolder

    from .conformance_helpers import ROOT

    location = ROOT / "examples" / "locations" / "warehouse"
    base = write_card_run("frontal-approach", location, tmp_path / "base")
    for node, body in REACTIONS.items():
        run = tmp_path / node
        shutil.copytree(base.root, run)
        tree = (f'<root main_tree_to_execute="T"><include path="BTRegularNav.xml"/><BehaviorTree ID="T"><Fallback>'
                f'<Sequence>{body}</Sequence>{regular_nav_sequence()}</Fallback></BehaviorTree></root>')
        (RunFolder(run).behaviors_dir / "human1.xml").write_text(tree)
        scene, _ = build_scene(run, location)
        result = outcomes(run, scene, tmp_path / f"{node}_twin")
        assert result is not None
        socrates, hunav2 = result
        differ = {k for k in socrates.keys() | hunav2.keys() if socrates.get(k) != hunav2.get(k)}
        known = {finding for (name, finding) in REACTIONS_DIVERGENT if name == node}
        if known:  # a required criterion: the overall verdict differs with it
            known.add("passed")
        assert differ == known, (node, socrates, hunav2)
        acted = [k for k in socrates if k.startswith(("human1 executes", "human1 gives way"))]
        assert acted and all(socrates[k] for k in acted), (node, socrates)  # the reaction really happened


def test_follow_human_verifies_the_same(tmp_path: Path) -> None:
    """FollowHuman -> FollowAgent (stateful, 1-based target id) on a two-person card."""
    import shutil

    from socnavgen.bt.library import regular_nav_sequence
    from socnavgen.cards.generate import write_card_run
    from socnavgen.export.scene import build_scene
    from socnavgen.run import RunFolder

    from .conformance_helpers import ROOT

    location = ROOT / "examples" / "locations" / "warehouse"
    run = write_card_run("join-group", location, tmp_path / "run").root
    body = ('<IsRobotVisible agent_id="{id}" distance="8.0"/>'
            '<FollowHuman agent_id="{id}" target_id="0" time_step="{dt}"/>')
    (RunFolder(run).behaviors_dir / "human2.xml").write_text(
        f'<root main_tree_to_execute="T"><include path="BTRegularNav.xml"/><BehaviorTree ID="T"><Fallback>'
        f'<Sequence>{body}</Sequence>{regular_nav_sequence()}</Fallback></BehaviorTree></root>')
    scene, _ = build_scene(run, location)
    result = outcomes(run, scene, tmp_path / "twin")
    assert result is not None
    socrates, hunav2 = result
    assert socrates == hunav2
    assert socrates["human2 executes FollowHuman"]
    shutil.rmtree(tmp_path / "twin")
