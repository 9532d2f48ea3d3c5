"""LoadedRun: a run folder read once and passed on. The simulator and the verifier give the same Simulation,
the same reports and the same errors (file, line, hint) with it as with the folder's path, and read each file
once however many episodes use it."""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from socnavgen.errors import SocnavgenError
from socnavgen.location import load_location
from socnavgen.run import folder as folder_module
from socnavgen.run.loaded import LoadedRun, load_run
from socnavgen.sim import SimConfig, load_policy, load_simulation
from socnavgen.verify.runner import verify_trace
from tests.verify.verify_builders import make_give_way_run, make_location


@pytest.fixture
def run_and_location(tmp_path: Path) -> tuple[Path, object]:
    location_dir = make_location(tmp_path / "corridor")
    return make_give_way_run(tmp_path / "run", location_dir), load_location(location_dir)


@pytest.fixture
def reads(monkeypatch: pytest.MonkeyPatch) -> Counter:
    """How often each file of a run folder is read (validated models and behavior XML)."""
    seen: Counter = Counter()
    read_model, read_text = folder_module.RunFolder._read, folder_module.read_text_limited

    def counting_read(self, path, model):  # noqa: ANN001, ANN202
        seen[Path(path).name] += 1
        return read_model(self, path, model)

    def counting_text(path, *args):  # noqa: ANN001, ANN202
        seen[Path(path).name] += 1
        return read_text(path, *args)

    monkeypatch.setattr(folder_module.RunFolder, "_read", counting_read)
    monkeypatch.setattr(folder_module, "read_text_limited", counting_text)
    return seen


def _episode(run: object, location: object, seed: int) -> tuple[object, object]:
    sim = load_simulation(run, load_policy("waypoints"), SimConfig(timeout=20.0, seed=seed), location=location)
    trace = sim.run()
    return trace, verify_trace(run, trace, location=location)


def test_each_file_is_read_once_however_many_episodes(run_and_location, reads: Counter) -> None:  # noqa: ANN001
    root, location = run_and_location
    loaded = LoadedRun(root)
    for seed in range(3):
        _episode(loaded, location, seed)
    assert reads == {"paths.json": 1, "human1.xml": 1, "request.json": 1}  # no spec.json in this run
    reads.clear()
    for seed in range(3):  # the counter is real: with a path every episode reads again
        _episode(root, location, seed)
    assert reads["paths.json"] == 6 and reads["human1.xml"] == 6


def test_a_loaded_run_gives_the_same_traces_and_reports_as_its_path(run_and_location) -> None:  # noqa: ANN001
    root, location = run_and_location
    loaded = LoadedRun(root)
    for seed in range(3):
        by_path, by_loaded = _episode(root, location, seed), _episode(loaded, location, seed)
        assert np.array_equal(by_path[0].humans, by_loaded[0].humans)
        assert np.array_equal(by_path[0].robot, by_loaded[0].robot)
        assert by_path[0].meta == by_loaded[0].meta
        assert by_path[1].model_dump() == by_loaded[1].model_dump()
    assert any(f.kind == "meets" for f in by_loaded[1].findings)  # the report judged something


def _outcome(call) -> tuple[str, object]:  # noqa: ANN001
    """("error", the message as the user sees it) or ("result", the report as data)."""
    try:
        result = call()
    except SocnavgenError as exc:
        return "error", exc.render()
    return "result", result.model_dump()


@pytest.mark.parametrize("damage", ["paths_json", "paths_node", "tree", "spec"])
def test_errors_are_those_of_the_folder(run_and_location, damage: str) -> None:  # noqa: ANN001
    root, location = run_and_location
    trace = _episode(root, location, 0)[0]
    if damage == "paths_json":
        (root / "paths.json").write_text('{"robot": ["a1",\n  oops]}\n')
    elif damage == "paths_node":
        plan = json.loads((root / "paths.json").read_text())
        plan["robot"][1] = "zz9"
        (root / "paths.json").write_text(json.dumps(plan))
    elif damage == "tree":
        (root / "behaviors" / "human1.xml").write_text("<root>\n  <BehaviorTree ID='x'>\n</root>\n")
    else:
        (root / "spec.json").write_text('{"version": 1, "criteria": [{"id": "c1", "kind": "nope"}]}')
    policy = load_policy("waypoints")
    with pytest.raises(SocnavgenError) as info:
        load_simulation(root, policy, location=location)
    expected = info.value.render()
    assert {"paths_json": "paths.json:2: malformed JSON", "paths_node": "node 'zz9' is not in the scene graph", "tree": "human1.xml:",
            "spec": "spec.json: criteria.0.kind"}[damage] in expected
    loaded = LoadedRun(root)
    for _ in range(2):  # a file that fails is not kept: asking again gives the same error
        with pytest.raises(SocnavgenError) as info:
            load_simulation(loaded, policy, location=location)
        assert info.value.render() == expected
    by_path = _outcome(lambda: verify_trace(root, trace, location=location))
    assert by_path[0] == ("result" if damage in ("paths_node", "tree") else "error")  # the verifier's own rules
    assert _outcome(lambda: verify_trace(loaded, trace, location=location)) == by_path
    assert _outcome(lambda: verify_trace(LoadedRun(root), trace, location=location)) == by_path


def test_location_dependent_checks_are_kept_per_location_object(run_and_location) -> None:  # noqa: ANN001
    root, location = run_and_location
    loaded = LoadedRun(root)
    assert loaded.plan_mistakes(location) == [] and loaded.plan_mistakes(location) is loaded.plan_mistakes(location)
    builds = []
    assert loaded.for_location("k", location, lambda: builds.append(1) or "a") == "a"
    assert loaded.for_location("k", location, lambda: builds.append(1) or "b") == "a"
    other = load_location(location.root)  # the same folder loaded again is another object
    assert loaded.for_location("k", other, lambda: builds.append(1) or "c") == "c"
    assert builds == [1, 1]


def test_load_run_passes_a_loaded_run_through(tmp_path: Path) -> None:
    loaded = LoadedRun(tmp_path)
    assert load_run(loaded) is loaded
    assert load_run(tmp_path).root == tmp_path and load_run(str(tmp_path)).root == tmp_path
    assert loaded.derived("x", lambda: [1]) is loaded.derived("x", lambda: [2])
