"""Table III over fixtures: both verification columns and the eyes' column, and their totals."""

from __future__ import annotations

from socnavgen.evaluation.fixtures import FixtureRow, fixtures_markdown


def _row(name: str, first: bool | None, final: bool | None, eyes: bool | None) -> FixtureRow:
    return FixtureRow(fixture=name, location="home", humans=1, scenario_valid=True, paths_valid=True,
                      trees_valid=final is not None, first_attempt=True, verified=final, verified_first=first,
                      eyes_match=eyes)


def test_the_table_counts_first_answers_end_of_verify_and_agreement_with_the_eyes() -> None:
    rows = [_row("a", True, True, True), _row("b", False, True, False), _row("c", False, False, False),
            _row("d", None, None, None)]
    table = fixtures_markdown(rows).splitlines()
    assert "verified, first answers" in table[0] and "eyes: as its text says" in table[0]
    b = next(line for line in table if line.startswith("| b |"))
    assert "| no | **yes** |" in b  # first answers failed, the end of --verify passed
    total = [c.strip() for c in table[-1].split("|")]
    assert total[8:10] == ["1/4", "2/4"]  # verified: first answers, end of --verify
    assert "2/3 agree" in table[-1]  # b is a pass the eyes did not accept; d was not judged
