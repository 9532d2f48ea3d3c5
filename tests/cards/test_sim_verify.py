"""Card runs go through the headless simulator and the verifier like any run; the card's success
criteria become verifier findings."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.location import load_location

# Cards whose encounter the 2D simulator reproduces on the hospital map with the social-force robot.
MUST_PASS = {"blind-corner", "entering-room", "exiting-room", "entering-elevator", "exiting-elevator",
             "frontal-approach", "join-group", "leave-group", "leading-human", "crowd-navigation",
             "circular-crossing"}


def test_hospital_cards_simulate_and_verify(repo_root: Path, tmp_path: Path) -> None:
    verify = pytest.importorskip("socnavgen.verify")
    loc = repo_root / "examples/locations/hospital"
    if not loc.is_dir():
        pytest.skip("hospital location not present")
    outcomes: dict[str, bool] = {}
    for fit in fit_all(load_location(loc)):
        if not fit.fits:
            continue
        run = write_card_run(fit.card.name, loc, tmp_path / fit.card.name)
        report = verify.verify_run(run.root, simulate_options={"robot": "sfm", "timeout": 60.0})
        card_findings = [f for f in report.findings if f.source == "card"]
        assert len(card_findings) >= len(fit.card.criteria), fit.card.name
        assert (run.sim_dir / "trace.npz").is_file()
        outcomes[fit.card.name] = report.passed
    failed = sorted(name for name in MUST_PASS if not outcomes.get(name))
    assert not failed, f"cards that no longer verify: {failed}"
