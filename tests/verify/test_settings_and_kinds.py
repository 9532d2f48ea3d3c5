"""One home per verifier fact: VerifySettings is the only source of the thresholds' defaults (and of the
`verify` command's options), unknown or out-of-range thresholds are errors, criterion kinds are a registry that
covers the spec's kinds and the docs' table."""

from __future__ import annotations

import typing
from pathlib import Path

import pytest
from typer.testing import CliRunner

from socnavgen.run.spec import CriterionKind as SpecKinds
from socnavgen.verify import VerifySettings, verify_run
from socnavgen.verify import thresholds as T
from socnavgen.verify.criteria import CRITERION_KINDS
from socnavgen.verify.signals import SIGNAL_KINDS

from .verify_builders import cli_app

DOCS = Path(__file__).resolve().parents[2] / "docs" / "verify.md"


def test_the_registry_covers_every_kind_of_the_spec_and_the_docs() -> None:
    assert list(CRITERION_KINDS) == list(typing.get_args(SpecKinds))
    docs = DOCS.read_text()
    for name in CRITERION_KINDS:
        assert f"| `{name}` |" in docs, name
    for kind in SIGNAL_KINDS:
        assert kind.shown.split(",")[0].strip() in docs, kind.shown


def test_settings_defaults_come_from_the_thresholds_module() -> None:
    s = VerifySettings()
    assert (s.distance, s.near, s.passing, s.group_spread, s.deadlock_seconds, s.reaction_seconds) == (
        T.MEET_DISTANCE, T.NEAR_NODE, T.PASSING_DISTANCE, T.GROUP_SPREAD, T.DEADLOCK_SECONDS, T.REACTION_SECONDS)


def test_unknown_or_out_of_range_thresholds_are_errors(give_way_run: Path) -> None:
    with pytest.raises(TypeError, match="'distnace'"):
        verify_run(give_way_run, simulate_if_missing=False, distnace=1.0)  # before: silently ignored
    with pytest.raises(ValueError, match="near"):
        verify_run(give_way_run, simulate_if_missing=False, near=-1.0)
    with pytest.raises(ValueError, match="deadlock_seconds"):
        VerifySettings.with_overrides(deadlock_seconds=float("nan"))
    assert VerifySettings.with_overrides(distance=1.5, near=None).model_dump() == {**VerifySettings().model_dump(),
                                                                                  "distance": 1.5}


def test_the_cli_options_are_the_settings(give_way_run: Path) -> None:
    runner = CliRunner()
    text = runner.invoke(cli_app(), ["verify", "--help"], terminal_width=200).stdout
    for name in VerifySettings.model_fields:
        if name != "collisions_fail":
            assert f"--{name.replace('_', '-')}" in text, name
    assert f"default: {VerifySettings().deadlock_seconds}" in " ".join(text.split())
    bad = runner.invoke(cli_app(), ["verify", str(give_way_run), "--no-simulate", "--near", "-1"])
    assert bad.exit_code == 2 and "--near" in bad.output and "between 0 and 50" in bad.output  # the field's range
    zero = runner.invoke(cli_app(), ["verify", str(give_way_run), "--no-simulate", "--near", "0"])
    assert zero.exit_code != 0 and "near" in str(zero.exception)  # gt=0: VerifySettings says so
