"""RUN/sim/ is one set made from one trace: outputs carry what they were made from, a new simulation replaces
the whole set (verify.json and a GIF of an earlier trace included), a stale or half-written set is never
judged, one simulation per run folder at a time, and a run folder moved during a simulation is not recreated."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from socnavgen.run import RunFolder

from .conftest import no_traceback

WAREHOUSE = Path(__file__).resolve().parents[2] / "examples" / "locations" / "warehouse"


@pytest.fixture
def card_run(tmp_path: Path) -> Path:
    from socnavgen.cards.generate import write_card_run

    return write_card_run("blind-corner", WAREHOUSE, tmp_path / "bc").root


def test_a_new_simulation_replaces_the_whole_set(cli, card_run) -> None:  # noqa: ANN001
    """`simulate --robot straight` left the old verify.json saying PASSED beside a trace with collisions."""
    sim = card_run / "sim"
    assert cli("simulate", card_run, "--timeout", "30").code == 0
    assert cli("verify", card_run).code in (0, 1)
    assert (sim / "verify.json").is_file()
    (sim / "animation.gif").write_bytes(b"GIF89a an earlier trace's animation")
    assert cli("simulate", card_run, "--robot", "straight", "--timeout", "30").code == 0
    assert not (sim / "verify.json").exists() and not (sim / "animation.gif").exists()
    stamp = json.loads((sim / "outputs.json").read_text())
    assert stamp["made"]["robot"] == "straight" and set(stamp["files"]) == {"trace.npz", "metrics.json",
                                                                            "trajectories.png"}


def test_verify_never_judges_a_trace_of_files_that_changed(cli, card_run) -> None:  # noqa: ANN001
    """`verify` after editing paths.json judged the stale trace (and said PASSED where a fresh run fails)."""
    assert cli("simulate", card_run, "--robot", "waypoints", "--timeout", "30").code == 0
    paths = card_run / "paths.json"
    paths.write_text(json.dumps(json.loads(paths.read_text()), indent=1))
    refused = cli("verify", card_run, "--no-simulate")
    assert refused.code == 2 and no_traceback(refused.err)
    assert "stale simulation: paths.json changed since" in refused.err and "socnavgen simulate RUN" in refused.err
    redone = cli("verify", card_run)
    assert redone.code in (0, 1) and "paths.json changed since" in redone.err and "simulating again" in redone.err
    stamp = json.loads((card_run / "sim" / "outputs.json").read_text())
    assert stamp["made"]["robot"] == "waypoints"  # simulated again as it was made, not with another robot
    assert "simulating again" not in cli("verify", card_run).err  # now current


def test_a_kill_between_two_writes_leaves_no_set_that_looks_complete(cli, card_run, monkeypatch) -> None:  # noqa: ANN001
    from socnavgen.sim.outputs import files as outputs

    assert cli("simulate", card_run, "--timeout", "30").code == 0

    def killed(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202 - the process dies after the trace was written
        raise KeyboardInterrupt

    monkeypatch.setattr(outputs, "write_outputs", killed)
    assert cli("simulate", card_run, "--robot", "straight", "--timeout", "30").code == 130
    sim = card_run / "sim"
    assert (sim / "trace.npz").is_file() and not (sim / "metrics.json").exists()  # not the earlier trace's
    assert json.loads((sim / "outputs.json").read_text()) == {"complete": False}
    refused = cli("verify", card_run, "--no-simulate")
    assert refused.code == 2 and "interrupted before its outputs were complete" in refused.err


def test_a_trace_without_any_record_is_judged_as_it_is_and_said_so(cli, card_run) -> None:  # noqa: ANN001
    """A trace made by hand or by an older socnavgen (no outputs.json at all) is judged, with a note."""
    assert cli("simulate", card_run, "--timeout", "30").code == 0
    (card_run / "sim" / "outputs.json").unlink()
    result = cli("verify", card_run, "--no-simulate")
    assert result.code in (0, 1) and "has no outputs.json" in result.err and "judged as it is" in result.err


def test_two_simulations_of_one_run_folder_are_refused(cli, card_run) -> None:  # noqa: ANN001
    """Two concurrent `simulate` on one folder left a trace and metrics from different robots."""
    with RunFolder(card_run).lock():
        result = cli("simulate", card_run, "--timeout", "30")
    assert result.code == 2 and "in use by another socnavgen process" in result.err
    assert not (card_run / "sim").exists()


def test_a_run_folder_moved_during_the_simulation_is_not_recreated(cli, card_run, monkeypatch) -> None:  # noqa: ANN001
    """A run folder renamed during `simulate` got its outputs written to a recreated old path."""
    from socnavgen.sim import Simulation

    real = Simulation.run

    def run_then_move(self, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        trace = real(self, *args, **kwargs)
        card_run.rename(card_run.with_name("moved"))
        return trace

    monkeypatch.setattr(Simulation, "run", run_then_move)
    result = cli("simulate", card_run, "--timeout", "30")
    assert result.code == 2 and no_traceback(result.err) and "was moved, renamed or deleted" in result.err
    assert not card_run.exists() and not (card_run.with_name("moved") / "sim").exists()


def test_simulate_a_missing_folder(cli, tmp_path) -> None:  # noqa: ANN001
    """`simulate runs/nope` said "no request.json" instead of "no such folder"."""
    result = cli("simulate", tmp_path / "nope")
    assert result.code == 2 and "no such run folder" in result.err and no_traceback(result.err)
    assert not (tmp_path / "nope").exists()


def test_two_robots_on_one_run_keep_their_own_outputs(cli, card_run, tmp_path) -> None:  # noqa: ANN001
    """`simulate --out DIR`: a second robot simulated on the same run no longer replaces the first one's set;
    figures in vector formats and an MP4 on request; a wrong format is one message, exit 2."""
    a, b = tmp_path / "scripted", tmp_path / "straight"
    assert cli("simulate", card_run, "--timeout", "8", "--out", a, "--figures", "png,svg,pdf").code == 0
    assert cli("simulate", card_run, "--timeout", "8", "--robot", "straight", "--out", b, "--mp4").code == 0
    assert json.loads((a / "outputs.json").read_text())["made"]["robot"] == "scripted"
    assert json.loads((b / "outputs.json").read_text())["made"]["robot"] == "straight"
    assert (a / "trajectories.svg").read_text().lstrip().startswith("<?xml")
    assert (a / "trajectories.pdf").read_bytes().startswith(b"%PDF")
    assert (b / "animation.mp4").read_bytes()[4:8] == b"ftyp" and not (b / "trajectories.svg").exists()
    assert not (card_run / "sim").exists()  # RUN/sim untouched
    wrong = cli("simulate", card_run, "--out", a, "--figures", "png,tiff")
    assert wrong.code == 2 and "tiff" in wrong.err and "Traceback" not in wrong.err
