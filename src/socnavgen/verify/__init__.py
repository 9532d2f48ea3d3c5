"""Verification: derive checkable expectations from a run's paths, trees and card, and judge them on the
simulation trace (pass/fail with evidence)."""

from socnavgen.verify.models import Expectation, Finding, VerifyReport, VerifySettings
from socnavgen.verify.runner import verify_run, verify_trace

__all__ = ["Expectation", "Finding", "VerifyReport", "VerifySettings", "verify_run", "verify_trace"]
