"""JSON extraction and repair from free-text model replies."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socnavgen.llm.jsonrepair import JSONRepairError, extract_json

EXPECTED = {"scenario": "blind corner", "humans": [{"name": "human1", "path": ["ab", "c9"]}], "ok": True,
            "speed": 1.5, "note": None}


@pytest.mark.parametrize("text", [
    json.dumps(EXPECTED),
    "Here is the scenario:\n```json\n" + json.dumps(EXPECTED, indent=2) + "\n```\nLet me know!",
    "```\n" + json.dumps(EXPECTED) + "\n```",
    "Sure. " + json.dumps(EXPECTED) + " Hope this helps.",
    repr(EXPECTED),  # Python literal: single quotes, True, None
    "{'scenario': 'blind corner', 'humans': [{'name': 'human1', 'path': ['ab', 'c9',],},], 'ok': true,"
    " 'speed': 1.5, 'note': null,}",
    '{scenario: "blind corner", humans: [{name: "human1", path: ["ab", "c9"]}], ok: True, speed: 1.5, note: None}',
    '{\n  "scenario": "blind corner", // the title\n  "humans": [{"name": "human1", "path": ["ab", "c9"]}],\n'
    '  /* flags */ "ok": true,\n  "speed": 1.5,\n  "note": null\n}',
    '{"scenario": "blind corner"\n "humans": [{"name": "human1", "path": ["ab",\n "c9"]}]\n "ok": true, "speed": +1.5,'
    ' "note": null}',  # missing commas at line ends and between items
    "```python\nprint('no')\n```\n```json\n" + json.dumps(EXPECTED) + "\n```",  # the JSON block wins
])
def test_repairs_common_slips(text):
    assert extract_json(text) == EXPECTED


def test_unescaped_quotes_inside_a_string_are_kept():
    assert extract_json('{"say": "he shouts "stop" and waits", "n": 1}') == {"say": 'he shouts "stop" and waits',
                                                                           "n": 1}
    assert extract_json("{'say': 'it's late'}") == {"say": "it's late"}


def test_keys_with_spaces_and_numbers():
    assert extract_json("{Scenario Description: 'x', HUMAN 1: {'path': [1, 2]}}") == {
        "Scenario Description": "x", "HUMAN 1": {"path": [1, 2]}}


def test_escapes_and_unicode():
    text = r"""{'a': 'tab\there', 'b': "\u00e9\ud83d\ude00", 'c': '\x41', 'd': "line
break"}"""
    assert extract_json(text) == {"a": "tab\there", "b": "é😀", "c": "A", "d": "line\nbreak"}


def test_prose_brackets_before_the_object_are_skipped():
    assert extract_json("[Note] I think {'x': 1} is right") == {"x": 1}


def test_array_expected():
    assert extract_json("The path is ['ab', 'cd'].", expect="array") == ["ab", "cd"]


@pytest.mark.parametrize("text, words", [
    ("", "empty"),
    ("I cannot help with that.", "no JSON object"),
    ('{"a": 1, "b": [1, 2', "not closed"),
    ('{"a": 1, "b": "unterminated}', "not closed"),
    ('{"a": nonsense}', "'nonsense'"),
])
def test_unreadable_replies_explain_what_is_wrong(text, words):
    with pytest.raises(JSONRepairError) as info:
        extract_json(text)
    assert words in str(info.value)


def test_syntax_errors_say_where():
    with pytest.raises(JSONRepairError, match=r"line 3, column"):
        extract_json('{\n "a": 1,\n "b" 2\n}')


def test_too_deep_nesting_is_an_error_not_a_crash():
    with pytest.raises(JSONRepairError):
        extract_json("{'a': " + "[" * 5000 + "]" * 4999 + "}")


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | st.text(),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(), children, max_size=4),
    max_leaves=20)
json_objects = st.dictionaries(st.text(), json_values, max_size=5)


@settings(max_examples=100, deadline=None)
@given(json_objects)
def test_valid_json_round_trips(value):
    assert extract_json(json.dumps(value)) == value
    assert extract_json(json.dumps(value, indent=2, ensure_ascii=False)) == value


@settings(max_examples=100, deadline=None)
@given(json_objects, st.sampled_from(["", "Here you go:\n", "Sure!\n```json\n"]), st.sampled_from(["", "\n```", " Done."]))
def test_json_wrapped_in_prose_or_fences(value, before, after):
    assert extract_json(before + json.dumps(value) + after) == value


python_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(alphabet=st.characters(blacklist_categories=("Cs",))),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(min_size=1), children, max_size=4),
    max_leaves=20)


@settings(max_examples=100, deadline=None)
@given(st.dictionaries(st.text(min_size=1), python_values, max_size=5))
def test_python_literals_parse(value):
    assert extract_json(repr(value)) == value


def dumps_with_trailing_commas(value) -> str:
    if isinstance(value, dict):
        return "{" + "".join(f"{json.dumps(k)}: {dumps_with_trailing_commas(v)}," for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + "".join(dumps_with_trailing_commas(v) + "," for v in value) + "]"
    return json.dumps(value)


@settings(max_examples=100, deadline=None)
@given(json_objects)
def test_trailing_commas_are_forgiven(value):
    assert extract_json(dumps_with_trailing_commas(value)) == value


@settings(max_examples=150, deadline=None)
@given(st.text(max_size=200))
def test_never_crashes_on_arbitrary_text(text):
    try:
        value = extract_json(text)
    except JSONRepairError as exc:
        assert str(exc)
    else:
        assert isinstance(value, dict)


def test_xml_with_unescaped_attribute_quotes_inside_a_string():
    text = ('{"reasoning": "stop when close", "tree": "<root main_tree_to_execute="HumanTree">\n'
            '  <BehaviorTree ID="HumanTree"><Sequence><IsRobotClose agent_id="{id}" distance="2.0"/>'
            '</Sequence></BehaviorTree>\n</root>"}')
    value = extract_json(text)
    assert value["reasoning"] == "stop when close"
    assert value["tree"].startswith('<root main_tree_to_execute="HumanTree">')
    assert 'distance="2.0"/>' in value["tree"] and value["tree"].endswith("</root>")
