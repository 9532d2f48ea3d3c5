"""The labelled corpus (corpus.py): the verifier's verdict is right on every trace, the failing criterion is
the intended one with the intended blame, and every robustness has the sign of its verdict."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.verify import verify_trace

from .corpus import CASES, Case, base_scene, base_spec, build, make_corner_location, write_case_run


@pytest.fixture(scope="module")
def locations(tmp_path_factory: pytest.TempPathFactory) -> dict[bool, Path]:
    root = tmp_path_factory.mktemp("corpus")
    return {True: make_corner_location(root / "blind"), False: make_corner_location(root / "open", blind=False)}


def _matches(finding, key: str) -> bool:  # noqa: ANN001
    return finding.criterion == key or key in finding.name


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_corpus_verdict(case: Case, locations: dict[bool, Path], tmp_path: Path) -> None:
    spec = case.spec(base_spec()) if case.spec is not None else None
    run = write_case_run(tmp_path / case.name, locations[case.blind], spec)
    report = verify_trace(run, build(case.scene(base_scene())))
    lines = "\n".join(f"{'ok ' if f.passed else 'FAIL'} {f.criterion or ''} {f.name}: {f.evidence} [{f.blame}]"
                      for f in report.findings)
    assert report.passed is case.passes, lines
    assert report.spec is (spec is not None)
    for f in report.findings:
        if f.robustness is not None:
            assert (f.robustness >= 0) == f.passed, f"{f.name}: robustness {f.robustness} vs passed {f.passed}"
        if not f.passed and f.required:
            assert f.blame in ("robot_script", "paths", "behaviors", "spec"), f.name
    if case.passes:
        return
    target = [f for f in report.findings if _matches(f, case.failing or "")]
    assert target, f"no finding {case.failing!r}:\n{lines}"
    bad = next((f for f in target if not f.passed), None)
    assert bad is not None, f"{case.failing} should fail:\n{lines}"
    assert bad.required
    assert (bad.blame, bad.blame_human) == (case.blame, case.blame_human), lines
    assert case.failing in report.feedback(bad.blame) or bad.name in report.feedback(bad.blame)


def test_corpus_is_large_enough() -> None:
    assert len(CASES) >= 40
    assert sum(not c.passes for c in CASES) >= 33
    names = {c.name for c in CASES}  # issue 25: each strict rule fails its mutation and passes the real event
    assert {"touching", "met_at_start_without_approach", "gives_way_without_being_in_the_way",
            "follows_through_a_wall", "jittering_deadlock", "run_of_a_tenth_of_a_second"} <= names
    assert {"six_cm_apart", "person_waits_at_its_place", "base"} <= names


def test_a_run_in_which_nothing_could_happen_says_only_that(locations: dict[bool, Path], tmp_path: Path) -> None:
    """A 0.1 s run whose robot's goal is its start: every finding fails for that one reason, with no robustness
    and no hint about the rest (a 0.1 s trace tells nothing about meetings, reactions or following)."""
    case = next(c for c in CASES if c.name == "run_of_a_tenth_of_a_second")
    report = verify_trace(write_case_run(tmp_path / "short", locations[True], base_spec()),
                          build(case.scene(base_scene())))
    assert not report.passed and report.findings
    for f in report.findings:
        assert not f.passed and f.robustness is None and f.blame == "paths"
        assert f.evidence.startswith("the run ended after 0.10 s") and "goal is where it starts" in f.evidence
