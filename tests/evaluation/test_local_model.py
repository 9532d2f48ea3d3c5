"""A tiny evaluation with the real in-process model: proves the harness drives a real backend end to
end (SmolLM2-135M proves the plumbing, not the quality: its validity numbers mean little)."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.evaluation.harness import EvalSettings, run_eval
from socnavgen.evaluation.report import table3, write_reports
from socnavgen.evaluation.suite import load_suite


@pytest.mark.local_model
@pytest.mark.timeout(900)
def test_tiny_eval_on_the_local_model(tmp_path: Path, repo_root: Path) -> None:
    suite = load_suite()
    suite.location = str(repo_root / "examples" / "locations" / "warehouse")
    suite.path_scenes = suite.path_scenes[1:2]  # Scene B: the blind corner
    settings = EvalSettings(llm="local", out=tmp_path / "eval", runs=1, tables=["III"], methods=["naive"],
                            verify=False, max_requeries=0, max_restarts=0, temperature=0.0, use_cache=False)
    outcomes = run_eval(suite, settings, suite.location)
    # The naive method (one prompt) keeps the test short; the pipeline's own local-model test covers ours.
    assert [o.method for o in outcomes] == ["naive"]
    assert all(o.finished for o in outcomes), [o.error for o in outcomes]
    assert all(o.attempts >= 1 and o.tokens > 0 for o in outcomes)
    # Validity is whatever the model achieved, but it must agree with what the run folder holds.
    for o in outcomes:
        folder = Path(o.folder)
        if o.valid:
            assert (folder / "paths.json").is_file() and list((folder / "behaviors").glob("*.xml"))
        elif o.method == "ours":
            assert o.error, "an invalid run says why in its manifest"
    rows = table3(outcomes, suite)
    assert [r.method for r in rows] == ["naive"] and rows[0].runs == 1
    write_reports(settings.out, outcomes, suite, settings.model_dump(mode="json"), None)
    assert "| naive | 1 |" in (settings.out / "results.md").read_text()
