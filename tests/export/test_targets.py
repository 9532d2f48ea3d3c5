"""The export targets are one registry whose names are bt.library.TARGETS (spelled once)."""

from __future__ import annotations

import pytest

from socnavgen.bt.library import TARGETS
from socnavgen.bt.validate import TARGETS as VALIDATOR_TARGETS
from socnavgen.errors import ValidationFailed
from socnavgen.export.models import FORMATS
from socnavgen.export.targets import REGISTRY, ExportTarget, get_target, summaries


def test_registry_names_are_the_library_targets() -> None:
    assert set(summaries()) == set(TARGETS) == set(REGISTRY)
    assert FORMATS == TARGETS == VALIDATOR_TARGETS
    for name in TARGETS:
        target = get_target(name)
        assert isinstance(target, ExportTarget) and target.name == name
    assert get_target("socrates").first_agent_id == 0
    assert get_target("hunav2").first_agent_id == get_target("hunav1").first_agent_id == 1
    assert get_target("hunav2").btcpp == "4" and get_target("socrates").btcpp == "3.8"


def test_unknown_target_is_one_clear_error() -> None:
    with pytest.raises(ValidationFailed, match="unknown export format 'gazebo'"):
        get_target("gazebo")
