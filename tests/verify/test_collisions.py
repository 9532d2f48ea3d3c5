"""Robot-human collisions: reported with evidence; a warning by default, a failure on request."""

from __future__ import annotations

from socnavgen.verify.evaluate import evaluate
from socnavgen.verify.models import Expectation, VerifyReport, VerifySettings

from .verify_builders import build_trace

NO_COLLISION = Expectation(kind="no_collision", name="robot never collides with a human", source="paths")


def _trace(gap_at_closest: float):
    # Robot stands at the origin; the human walks along x and stops with a surface gap of
    # `gap_at_closest` (centre distance = gap + 0.35 + 0.4).
    stop = gap_at_closest + 0.75
    xs = [3.0, 2.0, stop, stop]
    return build_trace([0, 1, 2, 3], [(0.0, 0.0)] * 4, [[(x, 0.0)] for x in xs], dt=1.0)


def test_clear_pass_reports_the_closest_gap() -> None:
    (finding,) = evaluate([NO_COLLISION], _trace(0.30))
    assert finding.passed and finding.required
    assert "closest gap 0.30 m to human1 at t=2.0 s" in finding.evidence


def test_overlap_is_a_warning_by_default_and_does_not_fail_the_report() -> None:
    (finding,) = evaluate([NO_COLLISION], _trace(-0.20))
    assert not finding.passed and not finding.required
    assert "overlap by 0.20 m at t=2.0 s (2 steps" in finding.evidence
    report = VerifyReport(run="r", passed=True, findings=[finding])
    assert report.failures == [] and report.warnings == [finding]


def test_overlap_fails_when_asked() -> None:
    (finding,) = evaluate([NO_COLLISION], _trace(-0.20), VerifySettings(collisions_fail=True))
    assert not finding.passed and finding.required


def test_touching_within_the_tolerance_is_not_a_collision() -> None:
    (finding,) = evaluate([NO_COLLISION], _trace(-0.03))
    assert finding.passed
