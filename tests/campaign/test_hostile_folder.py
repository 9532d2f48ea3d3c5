"""A campaign folder under hostile conditions: edited policies and scenarios re-run what they affect (and say
so), one writer at a time, unreadable Parquet files named and rebuilt around, an unfinished campaign reported
as such, a failed start leaves nothing behind."""

from __future__ import annotations

import json
import re
import shutil

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from socnavgen.campaign.report import write_report
from socnavgen.campaign.runner import run_campaign
from socnavgen.campaign.spec import load_campaign, parse_campaign
from socnavgen.errors import InputFileError, SocnavgenError
from tests.campaign.conftest import POLICIES, WAREHOUSE, campaign_yaml


def _campaign(tmp_path, seeds: int = 2, name: str = "test"):  # noqa: ANN001, ANN202
    """blind-corner x (waypoints, a policy file of its own) x seeds, written beside its policy file."""
    shutil.copy(POLICIES, tmp_path / "mine.py")
    file = tmp_path / "c.yaml"
    file.write_text(campaign_yaml(["blind-corner"], ["waypoints", "{name: mine, robot: 'mine.py:StraightThrough'}"],
                                  seeds, timeout=30).replace("name: test", f"name: {name}"))  # 1.0 m/s body: ~22 s
    return file


def _rows(out) -> list[dict]:  # noqa: ANN001
    return pq.read_table(out / "episodes.parquet").to_pylist()


def test_editing_a_policy_runs_its_episodes_again_and_only_those(tmp_path) -> None:  # noqa: ANN001
    """Editing a policy's code reported "4 already done, 0 run" with the old rows."""
    file, out = _campaign(tmp_path), tmp_path / "out"
    first = run_campaign(load_campaign(file), out, executor="inline")
    assert first.ran == 4 and first.rerun == {}
    before = {r["episode"]: r for r in _rows(out)}
    source = (tmp_path / "mine.py").read_text()
    (tmp_path / "mine.py").write_text(source.replace("* 1.2", "* 0.4"))  # a slower robot
    second = run_campaign(load_campaign(file), out, executor="inline")
    assert second.ran == 2 and second.skipped_done == 2
    assert second.rerun == {"policy mine's source or parameters changed": 2}
    after = {r["episode"]: r for r in _rows(out)}
    assert len(after) == 4
    for key, row in after.items():
        if row["policy"] == "waypoints":
            assert row["inputs"] == before[key]["inputs"] and row["sim_seconds"] == before[key]["sim_seconds"]
        else:
            assert row["inputs"] != before[key]["inputs"] and row["sim_seconds"] > before[key]["sim_seconds"]
    third = run_campaign(load_campaign(file), out, executor="inline")
    assert third.ran == 0 and third.rerun == {}


def test_changed_settings_and_scenario_files_run_again_and_more_seeds_run_only_the_new(tmp_path) -> None:  # noqa: ANN001
    file, out = _campaign(tmp_path, seeds=1), tmp_path / "out"
    run_campaign(load_campaign(file), out, executor="inline")
    file.write_text(file.read_text().replace("seeds: 1", "seeds: 2"))
    more = run_campaign(load_campaign(file), out, executor="inline")
    assert (more.ran, more.skipped_done, more.rerun) == (2, 2, {})
    file.write_text(file.read_text().replace("timeout: 20", "timeout: 19"))
    settings = run_campaign(load_campaign(file), out, executor="inline")
    assert settings.ran == 4 and settings.rerun == {"the simulation settings changed": 4}
    paths = out / "scenarios" / "warehouse" / "blind-corner" / "paths.json"
    paths.write_text(json.dumps(json.loads(paths.read_text())))  # same plan, other bytes: still another input
    scenario = run_campaign(load_campaign(file), out, executor="inline")
    assert scenario.rerun == {"scenario warehouse/blind-corner's files changed": 4}
    assert len(_rows(out)) == 4


def test_another_campaign_in_the_same_folder_is_refused(tmp_path) -> None:  # noqa: ANN001
    run_campaign(load_campaign(_campaign(tmp_path, seeds=1)), tmp_path / "out", executor="inline")
    other = _campaign(tmp_path, seeds=1, name="other")
    with pytest.raises(InputFileError, match="another campaign"):
        run_campaign(load_campaign(other), tmp_path / "out", executor="inline")


def test_two_runs_on_one_folder_are_refused(tmp_path) -> None:  # noqa: ANN001
    """Two `campaign run` on one folder both ran every episode."""
    from socnavgen.campaign.runner import LOCK_FILE
    from socnavgen.locks import acquire

    out = tmp_path / "out"
    out.mkdir()
    fd = acquire(out / LOCK_FILE, "test", "-")  # another process's lock (flock: another open file description)
    try:
        with pytest.raises(SocnavgenError, match="in use by another socnavgen process"):
            run_campaign(load_campaign(_campaign(tmp_path, seeds=1)), out, executor="inline")
    finally:
        import os

        os.close(fd)
    assert not (out / "parts").exists()


@pytest.mark.parametrize("damage", ["empty", "truncated"])
def test_an_unreadable_part_is_named_set_aside_and_its_episodes_run_again(tmp_path, damage) -> None:  # noqa: ANN001
    """A 0-byte or truncated part made resume crash with a pyarrow traceback on every retry."""
    file, out = _campaign(tmp_path), tmp_path / "out"
    run_campaign(load_campaign(file), out, executor="inline")
    (part,) = list((out / "parts").glob("part-*.parquet"))
    data = part.read_bytes()
    part.write_bytes(b"" if damage == "empty" else data[: len(data) // 2])
    (out / "episodes.parquet").unlink()  # as after a kill
    again = run_campaign(load_campaign(file), out, executor="inline")
    assert again.ran == 4 and len(_rows(out)) == 4
    assert len(again.problems) == 1 and part.name in again.problems[0] and "set aside" in again.problems[0]
    assert (out / "parts" / (part.name + ".broken")).is_file() and not part.exists()  # kept, not deleted


def test_report_survives_an_unreadable_table_and_says_so(tmp_path) -> None:  # noqa: ANN001
    file, out = _campaign(tmp_path, seeds=1), tmp_path / "out"
    run_campaign(load_campaign(file), out, executor="inline")
    (out / "episodes.parquet").write_bytes(b"PAR1 garbage")
    notes: list[str] = []
    files = write_report(out, gifs=0, resamples=200, notes=notes)
    md = files.summary
    assert any("episodes.parquet is unreadable" in n for n in notes)
    assert not any("unfinished" in n for n in notes)
    assert "episodes.parquet is unreadable" in md.read_text() and re.search(r"^\| mine +\|", md.read_text(), re.M)


def test_report_of_a_stopped_campaign_says_it_is_unfinished(tmp_path) -> None:  # noqa: ANN001
    """After a kill, `campaign report` presented the partial table as the result."""
    file, out = _campaign(tmp_path), tmp_path / "out"

    def stop_after_first(done: int, total: int) -> None:  # noqa: ARG001
        if done >= 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_campaign(load_campaign(file), out, executor="inline", batch_size=1, progress=stop_after_first)
    notes: list[str] = []
    md = write_report(out, gifs=0, resamples=200, notes=notes).summary
    assert notes and notes[0].startswith("unfinished campaign: 1 of 4 episodes")
    assert "unfinished campaign" in md.read_text()
    finished = run_campaign(load_campaign(file), out, executor="inline")
    assert finished.ran == 3
    notes.clear()
    write_report(out, gifs=0, resamples=200, notes=notes)
    assert notes == []


def test_a_failed_start_leaves_no_folder(tmp_path) -> None:  # noqa: ANN001
    """A campaign naming a missing run folder left an empty output folder behind."""
    file = tmp_path / "c.yaml"
    file.write_text("scenarios:\n  - runs: [nope]\npolicies: [waypoints]\nseeds: 1\n")
    with pytest.raises(InputFileError, match="not a run folder"):
        run_campaign(load_campaign(file), tmp_path / "new" / "out", executor="inline")
    assert not (tmp_path / "new" / "out").exists()
    kept = tmp_path / "kept"
    kept.mkdir()
    (kept / "mine.txt").write_text("a user's file")
    with pytest.raises(InputFileError):
        run_campaign(load_campaign(file), kept, executor="inline")
    assert (kept / "mine.txt").read_text() == "a user's file"


def test_report_of_a_deterministic_policy(tmp_path) -> None:  # noqa: ANN001
    """Identical values over seeds gave a CI whose lower end was above the mean by 1e-16, and matplotlib
    refused the negative error bar ('yerr' must not contain negative values)."""
    from socnavgen.campaign.aggregate import aggregate
    from socnavgen.campaign.columns import schema
    from socnavgen.campaign.plots import metric_bars, save
    from socnavgen.campaign.stats import bootstrap_mean

    est = bootstrap_mean(np.full(3, 0.7))
    assert est.low <= est.mean <= est.high
    rows = [{"episode": f"s|p|{k}", "scenario": "s", "policy": "p", "seed": k, "status": "ok", "success": True,
             "path_efficiency": 0.7, "time_to_reach_goal": 5.6} for k in range(3)]
    table = pa.Table.from_pylist(rows, schema=schema(["path_efficiency", "time_to_reach_goal"]))
    assert save(metric_bars(aggregate(table, resamples=200)), tmp_path, "bars").startswith(b"\x89PNG")


def test_spec_refuses_what_would_fail_later(tmp_path) -> None:  # noqa: ANN001
    base = campaign_yaml(["blind-corner"], ["waypoints"], 1)
    cases = {
        "seeds: [0, 100000000000000000000000000]": "seed 100000000000000000000000000 is out of range",
        "seeds: [-1, 2]": "seed -1 is out of range",
        "seeds: []": "give between 1 and 100000 seeds",
    }
    for seeds, message in cases.items():
        with pytest.raises(InputFileError, match=message.replace("(", r"\(")) as err:
            parse_campaign(base.replace("seeds: 1", seeds), file="c.yaml")
        assert err.value.line == 7
    with pytest.raises(InputFileError, match="36,000,000 steps") as err:
        parse_campaign(base.replace("{timeout: 40.0", "{dt: 0.0001, timeout: 3600"), file="c.yaml")
    assert err.value.line == 8


@pytest.mark.parametrize(("typo", "key", "line", "hint"), [
    ("policies:", "polices", 5, "did you mean policies?"),
    ("    locations:", "scenarios.0.locaitons", 4, "did you mean locations?"),
    ("simulation: {timeout", "simulation.timout", 8, "did you mean timeout?"),
])
def test_a_misspelled_key_is_named_with_its_line(typo, key, line, hint) -> None:  # noqa: ANN001
    """`locaitons:` was reported as `scenarios.0.cards: Extra inputs are not permitted`, `polices:` as
    `policies: Field required` on line 1."""
    wrong = {"policies:": "polices:", "    locations:": "    locaitons:",
             "simulation: {timeout": "simulation: {timout"}[typo]
    text = campaign_yaml(["blind-corner"], ["waypoints"], 1).replace(typo, wrong)
    with pytest.raises(InputFileError) as err:
        parse_campaign(text, file="c.yaml")
    assert err.value.message == f"{key}: unknown key {key.rsplit('.', 1)[-1]!r}"
    assert err.value.line == line and err.value.hint == hint


def test_an_unknown_card_gets_a_suggestion() -> None:
    with pytest.raises(InputFileError, match="blind-coner: did you mean blind-corner"):
        parse_campaign(campaign_yaml(["blind-coner"], ["waypoints"], 1))


def test_a_location_of_the_same_name_is_not_merged(tmp_path) -> None:  # noqa: ANN001
    """Two locations whose location.yaml share a name were merged: the second one's cards were never run."""
    twin = tmp_path / "twin"
    shutil.copytree(WAREHOUSE, twin)
    text = campaign_yaml(["blind-corner"], ["waypoints"], 1).replace(f"[{WAREHOUSE}]", f"[{WAREHOUSE}, {twin}]")
    with pytest.raises(InputFileError, match="two locations are both named 'warehouse'"):
        run_campaign(parse_campaign(text), tmp_path / "out", executor="inline")
