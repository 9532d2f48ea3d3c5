"""A ROS 2 bag of a run is judged like its simulation: a bag written from our own trace reads back to the
same verdict, findings and metrics (round trip, both hunav_msgs flavours, MCAP and sqlite3); bags recorded
by others (hand-built here with rosbags) are mapped to the run's humans, and every way a bag can be wrong
ends in one message naming the file and what to do."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from socnavgen.bag import BagError, BagReadOptions, BagWriteOptions, ReadTopics, bag_to_trace, write_bag
from socnavgen.location import load_location
from socnavgen.run import LoadedRun
from socnavgen.sim.metrics import compute_metrics
from socnavgen.verify import verify_trace

from .bag_builders import HandBag, corpus_agents, steps, write_hand_bag
from .corpus import CASES, base_plan, base_scene, base_spec, build, make_corner_location, write_case_run

ROUND_TRIP = ["base", "base_without_spec", "excuse_me_never_said", "collision", "group_apart"]


@pytest.fixture(scope="module")
def corner(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_corner_location(tmp_path_factory.mktemp("bag_corner") / "corner")


@pytest.fixture
def run(tmp_path: Path, corner: Path) -> Path:
    return write_case_run(tmp_path / "run", corner, base_spec())


def _same_metrics(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for key, value in a.items():
        if isinstance(value, float) and value is not None and b[key] is not None:
            assert math.isclose(value, b[key], rel_tol=1e-9, abs_tol=1e-9), key
        else:
            assert value == b[key], key


@pytest.mark.parametrize("name", ROUND_TRIP)
def test_a_bag_of_our_trace_reads_back_to_the_same_verdict_and_metrics(name: str, tmp_path: Path,
                                                                      corner: Path) -> None:
    case = next(c for c in CASES if c.name == name)
    spec = case.spec(base_spec()) if case.spec is not None else None
    loaded = LoadedRun(write_case_run(tmp_path / "run", corner, spec))
    location = loaded.location()
    trace = build(case.scene(base_scene()))
    write_bag(trace, tmp_path / "episode", location=location, plan=loaded.paths())
    back = bag_to_trace(tmp_path / "episode", loaded.paths(), location).trace
    assert back.steps == trace.steps and back.human_names == trace.human_names
    np.testing.assert_allclose(back.robot, trace.robot, atol=1e-9)
    np.testing.assert_allclose(back.humans, trace.humans, atol=1e-9)
    for column in ("action", "succeeded", "human_gesture", "robot_gesture", "behavior_state"):
        assert np.array_equal(getattr(back, column), getattr(trace, column)), column
    before, after = verify_trace(loaded, trace, location=location), verify_trace(loaded, back, location=location)
    assert after.passed is before.passed is case.passes
    assert [(f.name, f.passed, f.blame, f.blame_human) for f in after.findings] == \
        [(f.name, f.passed, f.blame, f.blame_human) for f in before.findings]
    for f, g in zip(before.findings, after.findings, strict=True):
        assert (f.robustness is None) == (g.robustness is None)
        if f.robustness is not None:
            assert math.isclose(f.robustness, g.robustness, abs_tol=1e-9), f.name
    _same_metrics(compute_metrics(trace, location), compute_metrics(back, location))


def test_round_trip_with_upstream_hunav_msgs_and_a_coarser_step(tmp_path: Path, run: Path) -> None:
    """Upstream hunav_msgs carry no gestures: positions survive, gestures are gone; ids start at 1 as the
    hunav2 export numbers agents, and --dt resamples (linear between recorded states)."""
    loaded = LoadedRun(run)
    trace = build(base_scene())
    write_bag(trace, tmp_path / "up", location=loaded.location(), plan=loaded.paths(),
              options=BagWriteOptions(flavour="hunav"))
    got = bag_to_trace(tmp_path / "up", loaded.paths(), loaded.location())
    assert any("hunav (the bag's own definition)" in n for n in got.notes)
    assert got.agent_ids == {"human1": 1, "human2": 2, "human3": 3}
    assert not got.trace.human_gesture.any() and got.trace.robot_gesture.any()  # /robot_gesture still there
    coarse = bag_to_trace(tmp_path / "up", loaded.paths(), loaded.location(), BagReadOptions(dt=0.25)).trace
    assert coarse.dt == 0.25 and coarse.steps == int(trace.t[-1] / 0.25) + 1
    k = 3  # t = 0.75 s lies between two recorded states 0.1 s apart: interpolated
    np.testing.assert_allclose(coarse.robot[k, 0], np.interp(0.75, trace.t, trace.robot[:, 0]), atol=1e-9)


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
@pytest.mark.parametrize("flavour", ["socrates", "hunav"])
def test_a_bag_recorded_elsewhere_is_read_with_the_right_definitions(storage: str, flavour: str, tmp_path: Path,
                                                                   run: Path) -> None:
    """sqlite3 bags (as ROS 2 Humble records them) carry no definitions: the flavour that decodes is found."""
    bag = write_hand_bag(tmp_path / "rec", HandBag(steps=steps(), flavour=flavour, storage=storage))
    loaded = LoadedRun(run)
    got = bag_to_trace(bag, loaded.paths(), loaded.location())
    assert got.notes[0].startswith(f"hunav_msgs: {flavour}")
    assert got.trace.steps == 81 and got.trace.dt == 0.05  # 4 s recorded at 10 Hz, resampled to the default
    np.testing.assert_allclose(got.trace.humans[40, 0, :2], [6.275, 6.025 - 1.0], atol=1e-9)
    assert got.trace.node_names == [] and (got.trace.action == -1).all()
    assert any("no behavior-tree activity" in n for n in got.notes)
    report = verify_trace(loaded, got.trace, location=loaded.location())
    assert report.findings  # judged by the same criteria (this short recording fails them)


def test_agents_are_matched_by_id_as_the_exports_number_them(tmp_path: Path, run: Path) -> None:
    loaded = LoadedRun(run)
    unnamed = ("actor_a", "actor_b", "actor_c")
    socrates = write_hand_bag(tmp_path / "s", HandBag(steps=steps(ids=(0, 1, 2), names=unnamed)))
    hunav = write_hand_bag(tmp_path / "h", HandBag(steps=steps(ids=(1, 2, 3), names=unnamed)))
    assert bag_to_trace(socrates, loaded.paths(), loaded.location()).agent_ids == {"human1": 0, "human2": 1,
                                                                                 "human3": 2}
    assert bag_to_trace(hunav, loaded.paths(), loaded.location()).agent_ids == {"human1": 1, "human2": 2,
                                                                              "human3": 3}
    mapped = write_hand_bag(tmp_path / "m", HandBag(steps=steps(ids=(7, 8, 9), names=unnamed)))
    with pytest.raises(BagError, match=r"id 7 \('actor_a'\).* not humans of this run.*ids 0, 1, 2 in a socrates"):
        bag_to_trace(mapped, loaded.paths(), loaded.location())
    got = bag_to_trace(mapped, loaded.paths(), loaded.location(),
                       BagReadOptions(agent_map={7: "human1", 8: "human2", 9: "human3"}))
    assert got.agent_ids == {"human1": 7, "human2": 8, "human3": 9}


def _error(tmp_path: Path, run: Path, bag: HandBag | Path, options: BagReadOptions | None = None) -> BagError:
    loaded = LoadedRun(run)
    path = bag if isinstance(bag, Path) else write_hand_bag(tmp_path / "bad", bag)
    with pytest.raises(BagError) as info:
        bag_to_trace(path, loaded.paths(), loaded.location(), options)
    assert str(path) in str(info.value)
    return info.value


def test_missing_topics_are_named_with_what_the_bag_has(tmp_path: Path, run: Path) -> None:
    err = _error(tmp_path, run, HandBag(steps=steps(), humans_topic=None, extra_topics=["/chatter"]))
    assert "no /human_states topic" in err.message and "/chatter (std_msgs/msg/String)" in err.message
    assert "ros2 bag record" in err.hint
    err = _error(tmp_path / "b", run, HandBag(steps=steps(), humans_topic="/sim/human_states"))
    assert err.hint == "pass --humans-topic /sim/human_states"
    loaded = LoadedRun(run)
    got = bag_to_trace(tmp_path / "b" / "bad", loaded.paths(), loaded.location(),
                       BagReadOptions(topics=ReadTopics(humans="sim/human_states")))
    assert got.trace.steps == 81


def test_a_topic_of_the_wrong_type_is_refused(tmp_path: Path, run: Path) -> None:
    err = _error(tmp_path, run, HandBag(steps=steps(), humans_topic="/other", extra_topics=["/human_states"]))
    assert "/human_states carries std_msgs/msg/String, not hunav_msgs/msg/Agents" in err.message


def test_unknown_and_missing_agents(tmp_path: Path, run: Path) -> None:
    extra = steps()
    for step in extra:
        step.humans.append(corpus_agents(step.t)[0].__class__(42, "stranger", 0.0, 0.0))
    assert "id 42 ('stranger')" in _error(tmp_path, run, HandBag(steps=extra)).message
    fewer = steps()
    for step in fewer:
        step.humans = step.humans[:2]
    err = _error(tmp_path / "b", run, HandBag(steps=fewer))
    assert "human3 of this run never appear" in err.message


def test_clock_jumps_are_refused(tmp_path: Path, run: Path) -> None:
    back = steps()
    for step in back[20:]:
        step.log = step.t  # the recording's clock goes on...
        step.t -= 1.5  # ...while the simulator's restarts earlier (a reset)
    err = _error(tmp_path, run, HandBag(steps=back))
    assert "clock jumps back by 1.400 s at t = 1.900 s" in err.message and "one episode per bag" in err.hint
    gap = steps()
    for step in gap[20:]:
        step.t += 10.0
        step.log = step.t
    err = _error(tmp_path / "b", run, HandBag(steps=gap))
    assert "for 10.10 s" in err.message and "--max-gap" in err.hint
    assert bag_to_trace(tmp_path / "b" / "bad", LoadedRun(run).paths(), LoadedRun(run).location(),
                        BagReadOptions(max_gap=20.0)).trace.steps > 0


def test_truncated_and_damaged_files(tmp_path: Path, run: Path) -> None:
    good = write_hand_bag(tmp_path / "ok", HandBag(steps=steps()))
    mcap = next(good.glob("*.mcap"))
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(mcap.read_bytes()[: mcap.stat().st_size // 2])
    err = _error(tmp_path, run, cut)
    assert "truncated" in err.message and "mcap recover" in err.hint
    sql = write_hand_bag(tmp_path / "sql", HandBag(steps=steps(), storage="sqlite3"))
    db = next(sql.glob("*.db3"))
    cut_db = tmp_path / "cut.db3"
    cut_db.write_bytes(db.read_bytes()[: db.stat().st_size // 2])
    assert "truncated or damaged" in _error(tmp_path, run, cut_db).message
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not a bag at all" * 10)
    assert "truncated or damaged" in _error(tmp_path, run, junk).message
    assert "not a ROS 2 bag" in _error(tmp_path, run, tmp_path / "ok" / "metadata.yaml").message
    (tmp_path / "ok" / "metadata.yaml").write_text("rosbag2_bagfile_information: [unclosed")
    assert "metadata.yaml is unusable" in _error(tmp_path, run, tmp_path / "ok").message


def test_a_recording_of_another_scenario_is_refused(tmp_path: Path, run: Path) -> None:
    regrouped = steps(groups=(-1, 1, 1))
    assert "in group 1 in the recording but in group 0" in _error(tmp_path, run, HandBag(steps=regrouped)).message
    moved = steps()
    for step in moved:
        step.robot = (step.robot[0] + 8.0, step.robot[1])
    err = _error(tmp_path / "b", run, HandBag(steps=moved))
    assert "the robot starts at" in err.message and "does not match this run" in err.message


def test_a_cli_bag_verdict_and_its_messages(tmp_path: Path, run: Path, corner: Path) -> None:
    from tests.export.test_cli import run_cli

    loaded = LoadedRun(run)
    write_bag(build(base_scene()), tmp_path / "episode", location=load_location(corner), plan=base_plan())
    result = run_cli("verify", str(run), "--bag", str(tmp_path / "episode"))
    assert result.returncode == 0, result.stdout + result.stderr
    assert "PASSED" in result.stdout and (run / "bags" / "episode" / "verify.json").is_file()
    assert (run / "bags" / "episode" / "metrics.json").is_file() and not (run / "sim" / "verify.json").exists()
    bad = write_hand_bag(tmp_path / "bad", HandBag(steps=steps(), humans_topic="/people"))
    result = run_cli("verify", str(run), "--bag", str(bad))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "no /human_states topic" in result.stderr and "--humans-topic /people" in result.stderr
    assert loaded.paths() == base_plan()
