"""Verification: monitor a run's acceptance criteria (spec.json, else derived from paths, trees and card) on
the simulation trace as signal temporal logic, with robustness, evidence, and blame for every failure."""

from socnavgen.verify.models import Expectation, Finding, VerifyReport, VerifySettings
from socnavgen.verify.runner import verify_run, verify_trace
from socnavgen.verify.stl import formula_problems

__all__ = ["Expectation", "Finding", "VerifyReport", "VerifySettings", "formula_problems", "verify_run",
           "verify_trace"]
