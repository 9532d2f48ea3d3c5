"""Prompt templates live as files in `templates/` (not strings in code) and are filled with
`string.Template`, whose `$name` placeholders leave the JSON braces of the prompts alone."""

from __future__ import annotations

import json
import string
from functools import cache
from importlib import resources
from typing import Any

import yaml


@cache
def template_text(name: str) -> str:
    return resources.files("socnavgen.proposal").joinpath("templates", name).read_text(encoding="utf-8")


def render(name: str, **values: object) -> str:
    """Fill template `name`; a missing value is a programming error (KeyError), never silent."""
    return string.Template(template_text(name)).substitute({k: str(v) for k, v in values.items()}).strip()


@cache
def template_data(name: str) -> Any:
    """Structured example data (JSON or YAML) shipped beside the templates."""
    text = template_text(name)
    return yaml.safe_load(text) if name.endswith((".yaml", ".yml")) else json.loads(text)
