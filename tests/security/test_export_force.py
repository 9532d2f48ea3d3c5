"""`export --force` never removes or replaces a file the export did not write (issue 30: it deleted
scratch/important/thesis.tex and scratch/notes.txt). The folder's marker lists what an export wrote, with a
digest: only those files (unchanged since) are replaced or removed by a re-export; anything else stays, or
the export refuses and lists it."""

from __future__ import annotations

import contextlib
import json
import random
from pathlib import Path

import pytest

from socnavgen.atomic_files import EXPORT_MARKER
from socnavgen.errors import InputFileError
from socnavgen.export import export_run

from .conftest import no_traceback


def files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def users_files(out: Path) -> dict[str, bytes]:
    mine = {"important/thesis.tex": b"\\chapter{Results}", "notes.txt": b"call the lab"}
    for rel, data in mine.items():
        (out / rel).parent.mkdir(parents=True, exist_ok=True)
        (out / rel).write_bytes(data)
    return mine


def test_force_writes_beside_the_users_files_and_keeps_them(run_dir: Path, tmp_path: Path, cli) -> None:  # noqa: ANN001
    out = tmp_path / "scratch"
    mine = users_files(out)
    refused = cli("export", run_dir, "--format", "socrates", "-o", out)
    assert refused.code == 2 and "--force" in refused.err and no_traceback(refused.err)
    done = cli("export", run_dir, "--format", "socrates", "-o", out, "--force")
    assert done.code == 0, done.err
    assert "left alone 2 file(s)" in done.out and "important/thesis.tex" in done.out
    assert {k: files(out)[k] for k in mine} == mine
    marker = (out / EXPORT_MARKER).read_text()
    assert "important/thesis.tex" not in marker and "hunav_agent_manager/config/custom_agents.yaml" in marker
    # a re-export without one of the humans removes that human's old tree, and only that
    paths = json.loads((run_dir / "paths.json").read_text())
    paths["humans"] = paths["humans"][:1]
    (run_dir / "paths.json").write_text(json.dumps(paths))
    (run_dir / "behaviors" / "human2.xml").unlink()
    again = cli("export", run_dir, "--format", "socrates", "-o", out)
    assert again.code == 0 and "removed 1 file(s)" in again.out and "LLMBT_1.xml" in again.out
    assert {k: files(out)[k] for k in mine} == mine and not (out / "hunav_agent_manager/behavior_trees/LLMBT_1.xml").exists()


def test_a_file_the_user_changed_after_the_export_is_never_replaced(run_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "export"
    export_run(run_dir, "socrates", out)
    readme = out / "README.md"
    readme.write_text(readme.read_text() + "\nmy launch notes\n")
    before = files(out)
    with pytest.raises(InputFileError, match="did not write.*README.md"):
        export_run(run_dir, "socrates", out)
    assert files(out) == before
    # removed from the new export: a changed file is kept, not deleted
    (out / "hunav_agent_manager/behavior_trees/LLMBT_1.xml").write_text("<root/>")
    readme.unlink()
    paths = json.loads((run_dir / "paths.json").read_text())
    paths["humans"] = paths["humans"][:1]
    (run_dir / "paths.json").write_text(json.dumps(paths))
    (run_dir / "behaviors" / "human2.xml").unlink()
    result = export_run(run_dir, "socrates", out)
    assert (out / "hunav_agent_manager/behavior_trees/LLMBT_1.xml").read_text() == "<root/>"
    assert "hunav_agent_manager/behavior_trees/LLMBT_1.xml" in result.kept


def test_a_hostile_or_old_marker_cannot_make_the_export_delete_files(run_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "export"
    outside = tmp_path / "outside.txt"
    outside.write_text("not yours")
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    (out / EXPORT_MARKER).write_text("written by socnavgen export\n" + json.dumps(
        {"format": 1, "files": {"../outside.txt": "0" * 64, "notes.txt": "0" * 64}}))
    export_run(run_dir, "socrates", out)
    assert outside.read_text() == "not yours" and (out / "notes.txt").read_text() == "mine"
    (out / EXPORT_MARKER).write_text("written by socnavgen export; replaced whole on re-export\n")  # before this change
    result = export_run(run_dir, "socrates", out)
    assert (out / "notes.txt").read_text() == "mine" and result.kept == ["notes.txt"]


@pytest.mark.parametrize("seed", range(6))
def test_whatever_the_folder_holds_no_file_the_export_did_not_write_is_lost(seed: int, run_dir: Path,
                                                                           tmp_path: Path) -> None:
    """Random user files (some at the very paths the export writes, some in its folders) before and between
    exports with and without --force: every one survives with its content, whether the export ran or refused."""
    rng = random.Random(seed)
    out = tmp_path / "out"
    candidates = ["notes.txt", "README.md", "a/b/c.txt", "hunav_agent_manager/mine.yaml",
                  "hunav_agent_manager/config/custom_agents.yaml", "hunav_agent_manager/behavior_trees/LLMBT_0.xml",
                  "hunav_gazebo_wrapper/config/keep.json", ".hidden"]
    mine: dict[str, bytes] = {}
    for round_ in range(3):
        for rel in rng.sample(candidates, rng.randint(0, 3)):
            target = out / rel
            if target.exists() and rel not in mine:
                continue  # a file of the export: leave it to the export
            target.parent.mkdir(parents=True, exist_ok=True)
            data = f"user {seed} {round_} {rel}".encode()
            target.write_bytes(data)
            mine[rel] = data
        with contextlib.suppress(InputFileError):
            export_run(run_dir, "socrates", out, force=rng.random() < 0.7)
        present = files(out) if out.exists() else {}
        assert {k: present.get(k) for k in mine} == mine
