"""Scenario generation: stage 1 (scenario), stage 2 (paths), stage 3 (behavior trees), the naive
baseline, and `generate()` that runs them into a run folder."""

from socnavgen.proposal.pipeline import Run, generate

__all__ = ["Run", "generate"]
