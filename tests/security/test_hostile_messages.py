"""Cases of issue 30 that printed a traceback (or nothing) where one message naming the file and what to do
belongs (exit 2), and model text that reached the terminal raw."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from .conftest import no_traceback

REPO = Path(__file__).resolve().parents[2]
WAREHOUSE = REPO / "examples" / "locations" / "warehouse"
POLICIES = REPO / "tests" / "campaign" / "policies.py"


@pytest.fixture
def card_run(tmp_path: Path) -> Path:
    from socnavgen.cards.generate import write_card_run

    return write_card_run("blind-corner", WAREHOUSE, tmp_path / "bc").root


@pytest.mark.parametrize(("robot", "message"), [
    ("os:system", "os:system is not a robot policy class"),
    (f"{POLICIES}:BrokenConstructor", "could not be created: RuntimeError: no model weights at /nonexistent"),
])
def test_a_policy_that_is_not_one_or_cannot_be_made(cli, card_run, robot, message) -> None:  # noqa: ANN001
    result = cli("simulate", card_run, "--robot", robot)
    assert result.code == 2 and message in result.err and no_traceback(result.err)


def test_a_campaign_whose_policy_cannot_be_made(cli, tmp_path) -> None:  # noqa: ANN001
    file = tmp_path / "c.yaml"
    file.write_text(f"scenarios:\n  - cards: [blind-corner]\n    locations: [{WAREHOUSE}]\n"
                    f"policies:\n  - {{name: broken, robot: '{POLICIES}:BrokenConstructor'}}\nseeds: 1\n")
    result = cli("campaign", "run", file, "-o", tmp_path / "out")
    assert result.code == 2 and no_traceback(result.err)
    assert "policy broken: robot policy" in result.err and "could not be created" in result.err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("option", ["--near", "--distance", "--passing", "--group-spread", "--deadlock-seconds"])
def test_verify_refuses_negative_thresholds(cli, card_run, option) -> None:  # noqa: ANN001
    """`verify --near -1` was accepted."""
    result = cli("verify", card_run, option, "-1")
    assert result.code == 2 and "is not a finite number" in result.err and "-1" in result.err


def test_location_show_refuses_an_infinite_resolution(cli, tmp_path) -> None:  # noqa: ANN001
    """A location whose map.yaml says `resolution: .inf` passed `location show`."""
    loc = tmp_path / "loc"
    shutil.copytree(WAREHOUSE, loc)
    text = (loc / "map.yaml").read_text()
    (loc / "map.yaml").write_text("\n".join("resolution: .inf" if line.startswith("resolution:") else line
                                            for line in text.splitlines()) + "\n")
    result = cli("location", "show", loc, "-o", tmp_path / "g.png")
    assert result.code == 2 and "map.yaml" in result.err and "resolution must be a positive number" in result.err
    assert not (tmp_path / "g.png").exists()


def test_a_replay_key_of_5000_digits(cli, tmp_path) -> None:  # noqa: ANN001
    """A replay file with a 5,000-digit human key raised Python's int-conversion ValueError."""
    script = tmp_path / "replay.yaml"
    script.write_text("stages:\n  behaviors:\n    ? " + "1" * 5000 + "\n    : ['<reply>']\n")
    result = cli("generate", "--location", WAREHOUSE, "--context", "c", "--task", "t", "--llm", f"replay:{script}",
                 "--out", tmp_path / "run")
    assert result.code == 2 and no_traceback(result.err)
    assert "replay.yaml: refused: a number with thousands of digits" in result.err
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize(("trigger", "words"), [
    ({"when": "at_encounter", "encounter": "e9"}, "names encounter e9, which is not in encounters"),
    ({"when": "human_within", "human": "human7"}, "names human7, who takes part in no encounter"),
])
def test_a_cue_for_what_does_not_exist_is_flagged(cli, card_run, trigger, words) -> None:  # noqa: ANN001
    """A spec cue for a human or encounter that does not exist was silently never fired."""
    spec_path = card_run / "spec.json"
    spec = json.loads(spec_path.read_text())
    spec["script"]["cues"].append({"trigger": trigger, "say": "EXCUSE ME"})
    spec_path.write_text(json.dumps(spec))
    result = cli("simulate", card_run)
    assert result.code == 2 and no_traceback(result.err)
    assert "spec.json" in result.err and words in result.err and "would never fire" in result.err


def test_verify_shows_terminal_escapes_in_criterion_text_as_text(cli, card_run) -> None:  # noqa: ANN001
    """Criterion text with ESC[2J (clear screen) was printed raw by `verify`: model text is untrusted."""
    from rich.console import Console

    from socnavgen.verify import verify_run
    from socnavgen.verify.report import report_table

    spec_path = card_run / "spec.json"
    spec = json.loads(spec_path.read_text())
    spec["criteria"][0]["text"] = "met \x1b[2J\x1b]0;owned\x07 [bold red]FAKE PASS[/]"
    spec_path.write_text(json.dumps(spec))
    result = cli("verify", card_run)
    assert result.code in (0, 1) and "\x1b" not in result.out and "\x07" not in result.out
    assert "met \\x1b[2J\\x1b]0;owned\\x07 [bold red]FAKE PASS[/]" in result.out
    wide = Console(width=400, record=True, file=open("/dev/null", "w"))  # noqa: SIM115 - nothing folded
    wide.print(report_table(verify_run(card_run, write=False)))
    text = wide.export_text()
    assert "\\x1b[2J" in text and "[bold red]FAKE PASS[/]" in text and "\x1b" not in text
