"""The campaign file: accepted forms and one clear error per mistake, naming its line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from socnavgen.campaign.spec import CardsSource, FolderSource, RunsSource, parse_campaign
from socnavgen.errors import InputFileError

GOOD = """name: demo
scenarios:
  - cards: [blind-corner]
    locations: [examples/locations/warehouse]
  - runs: [runs/a]
  - folder: runs/
policies:
  - waypoints
  - {name: mine, robot: my_policy.py:Mine}
seeds: 3
simulation: {timeout: 30}
metrics: [success, path_efficiency]
"""


def test_good_file_parses_with_shorthands() -> None:
    spec = parse_campaign(GOOD)
    assert [type(s) for s in spec.scenarios] == [CardsSource, RunsSource, FolderSource]
    assert [p.name for p in spec.policies] == ["waypoints", "mine"]
    assert spec.policies[0].robot == "waypoints"
    assert spec.policies[1].robot == f"{Path('my_policy.py').resolve()}:Mine"  # relative to the file's folder
    assert spec.seeds == [0, 1, 2]
    assert spec.simulation.timeout == 30 and spec.simulation.dt == 0.05
    assert spec.metrics == ["success", "path_efficiency"]


@pytest.mark.parametrize(("text", "line", "words"), [
    (GOOD.replace("blind-corner", "blind-corne"), 3, "unknown card"),
    (GOOD.replace("seeds: 3", "seeds: 0"), 10, "number of seeds"),
    (GOOD.replace("timeout: 30", "timeout: -1"), 11, "simulation.timeout"),
    (GOOD.replace("path_efficiency]", "path_eficiency]"), 12, "unknown metric"),
    (GOOD.replace("  - folder: runs/", "  - folders: runs/"), 6, "folders"),
    (GOOD.replace("name: mine", "name: waypoints"), 7, "repeated: waypoints"),  # the `policies:` line
    (GOOD.replace("seeds: 3", "seedz: 3"), 10, "seedz"),
    (GOOD.replace("policies:", "policies: [\n"), None, "malformed YAML"),
    ("- just a list\n", 1, "YAML mapping"),
])
def test_each_mistake_is_one_message_with_its_line(text: str, line: int | None, words: str) -> None:
    with pytest.raises(InputFileError) as info:
        parse_campaign(text, file="c.yaml")
    assert words in info.value.message
    if line is not None:
        assert info.value.line == line, info.value.render()


def test_cli_error_is_exit_2_without_traceback(tmp_path) -> None:  # noqa: ANN001
    bad = tmp_path / "c.yaml"
    bad.write_text(GOOD.replace("seeds: 3", "seeds: many"))
    code = "import sys; from socnavgen.cli import main; sys.argv = ['socnavgen', *sys.argv[1:]]; main()"
    done = subprocess.run([sys.executable, "-c", code, "campaign", "run", str(bad), "-o", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert "c.yaml:10" in done.stderr and "seeds" in done.stderr
    assert "Traceback" not in done.stderr


def test_policy_files_are_relative_to_the_campaign_file_and_checked_first(tmp_path) -> None:  # noqa: ANN001
    from socnavgen.campaign.runner import run_campaign
    from socnavgen.campaign.spec import load_campaign

    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "mine.py").write_text("from socnavgen.sim import RobotAction\n\nclass Still:\n"
                                                  "    def act(self, obs):\n        return RobotAction(0.0, 0.0)\n")
    file = tmp_path / "c.yaml"
    file.write_text(GOOD.replace("my_policy.py:Mine", "robots/mine.py:Still"))
    spec = load_campaign(file)
    assert spec.policies[1].robot == f"{(tmp_path / 'robots' / 'mine.py').resolve()}:Still"
    file.write_text(GOOD.replace("my_policy.py:Mine", "robots/missing.py:Still"))
    with pytest.raises(InputFileError) as info:
        run_campaign(load_campaign(file), tmp_path / "out", executor="inline")
    assert "policy mine" in info.value.message and "not found" in info.value.message
    assert not (tmp_path / "out" / "parts").exists()
