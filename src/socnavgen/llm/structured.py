"""Structured replies: tell the model what JSON to write, then read its reply into the stage's model.

Keys are matched loosely (SocRATES prompts ask for 'Scenario Description', 'HUMAN 1' ...) so that a
stage model with snake_case fields accepts them; mismatches are reported in words the model can act
on, because the caller sends that text back as the correction.
"""

from __future__ import annotations

import contextlib
import json
import re
import types
import typing
from typing import Any, TypeVar, Union

from pydantic import AliasChoices, AliasPath, BaseModel, ValidationError

from socnavgen.llm.jsonrepair import JSONRepairError, extract_json

T = TypeVar("T", bound=BaseModel)

MAX_ERRORS_SHOWN = 8


def json_schema(schema: type[BaseModel]) -> dict[str, Any]:
    return schema.model_json_schema()


def schema_text(schema: type[BaseModel]) -> str:
    """The schema as compact JSON, stable across runs (it is part of the cache key)."""
    return json.dumps(json_schema(schema), sort_keys=True, separators=(",", ":"))


def json_instruction(schema: type[BaseModel]) -> str:
    """Prompt text for servers without native structured output (also satisfies json_object mode,
    which requires the word JSON in the conversation)."""
    return ("Reply with one JSON object and nothing else (no prose, no code fences). "
            "It must match this JSON schema:\n" + json.dumps(json_schema(schema), separators=(",", ":")))


def parse_reply(raw: str, schema: type[T]) -> tuple[T | None, str | None]:
    """(value, None) when the reply validates, else (None, an explanation for the model)."""
    try:
        data = extract_json(raw, expect="object")
    except JSONRepairError as exc:
        advice = "" if "reply with" in str(exc) else " Reply again with only the corrected JSON object."
        return None, f"Your reply could not be read as JSON: {exc}.{advice}"
    with contextlib.suppress(Exception):  # a shape we do not walk: pydantic judges the keys as written
        data = normalise_keys(data, schema)
    try:
        return schema.model_validate(data), None
    except ValidationError as exc:
        return None, describe_validation_error(exc)
    except (ValueError, TypeError) as exc:  # a validator that raised something else
        return None, f"Your JSON could not be used: {exc}. Reply again with the whole corrected JSON object."


def describe_validation_error(exc: ValidationError) -> str:
    lines = []
    for err in exc.errors()[:MAX_ERRORS_SHOWN]:
        where = ".".join(str(part) for part in err["loc"]) or "(the whole object)"
        message = err["msg"]
        if err["type"] == "missing":
            message = "this field is required but missing"
        elif err["type"] == "extra_forbidden":
            message = "this field is not allowed"
        lines.append(f"- {where}: {message}")
    more = exc.error_count() - MAX_ERRORS_SHOWN
    if more > 0:
        lines.append(f"- ... and {more} more")
    return ("Your JSON does not match the required format:\n" + "\n".join(lines)
            + "\nReply again with the whole corrected JSON object.")


# ---- loose key matching ---------------------------------------------------------------------

def key_forms(name: str) -> tuple[str, str]:
    """('scenario_description', 'scenariodescription') for 'Scenario Description', 'scenario-description'..."""
    snake = re.sub(r"[^0-9a-z]+", "_", name.strip().lower()).strip("_")
    return snake, snake.replace("_", "")


def normalise_keys(data: Any, annotation: Any) -> Any:
    """Rename keys of `data` to the field names (or aliases) of the pydantic model they should fill,
    walking nested models, lists and dict values. Unknown keys are left alone for pydantic to judge."""
    annotation = _unwrap(annotation)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        if isinstance(data, dict):
            return _normalise_model(data, annotation)
        return data
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin in (list, set, frozenset, tuple) and isinstance(data, list) and args:
        if origin is tuple and not (len(args) == 2 and args[1] is Ellipsis):
            return [normalise_keys(item, arg) for item, arg in zip(data, args, strict=False)] + data[len(args):]
        return [normalise_keys(item, args[0]) for item in data]
    if origin is dict and isinstance(data, dict) and len(args) == 2:
        return {k: normalise_keys(v, args[1]) for k, v in data.items()}
    if origin in (Union, types.UnionType) and isinstance(data, dict):
        models = [a for a in (_unwrap(a) for a in args) if isinstance(a, type) and issubclass(a, BaseModel)]
        if models:
            best = max(models, key=lambda m: _match_count(data, m))
            return normalise_keys(data, best)
    return data


def _unwrap(annotation: Any) -> Any:
    while typing.get_origin(annotation) is typing.Annotated:
        annotation = typing.get_args(annotation)[0]
    return annotation


def _targets(model: type[BaseModel]) -> dict[str, tuple[str, Any]]:
    """normalised key form -> (key pydantic accepts, field annotation)."""
    table: dict[str, tuple[str, Any]] = {}
    by_name = bool(model.model_config.get("populate_by_name") or model.model_config.get("validate_by_name"))
    for name, field in model.model_fields.items():
        accepted = [field.alias] if field.alias else []
        accepted += _validation_aliases(field.validation_alias)
        if not accepted or by_name:
            accepted.append(name)
        for key in accepted:
            for form in key_forms(key):
                table.setdefault(form, (key, field.annotation))
        for form in key_forms(name):  # a reply using the python name when an alias exists
            table.setdefault(form, (accepted[0], field.annotation))
    return table


def _validation_aliases(alias: Any) -> list[str]:
    """The plain-string spellings in a validation_alias (str, AliasChoices or AliasPath)."""
    if alias is None:
        return []
    if isinstance(alias, str):
        return [alias]
    if isinstance(alias, AliasPath):
        return [alias.path[0]] if len(alias.path) == 1 and isinstance(alias.path[0], str) else []
    if isinstance(alias, AliasChoices):
        return [name for choice in alias.choices for name in _validation_aliases(choice)]
    return []


def _match_count(data: dict, model: type[BaseModel]) -> int:
    table = _targets(model)
    return sum(1 for k in data if isinstance(k, str) and any(f in table for f in key_forms(k)))


def _normalise_model(data: dict, model: type[BaseModel]) -> dict:
    table = _targets(model)
    if table and len(data) == 1:  # {"scenario": {...fields...}}: unwrap a single wrapper key
        (only_key, inner), = data.items()
        if isinstance(inner, dict) and _match_count(data, model) == 0 and _match_count(inner, model) > 0:
            data = inner
    result: dict[Any, Any] = {}
    for key, value in data.items():
        target = None
        if isinstance(key, str):
            snake, squashed = key_forms(key)
            target = table.get(snake) or table.get(squashed)
        if target is None:  # unknown key: still snake_cased, for models that allow extras or aliases
            snake = key_forms(key)[0] if isinstance(key, str) and key_forms(key)[0] else key
            result.setdefault(snake, value)
            continue
        accepted, annotation = target
        if accepted in result and key != accepted:
            continue  # two spellings of one field: the exact spelling (or the first one) wins
        result[accepted] = normalise_keys(value, annotation)
    return result
