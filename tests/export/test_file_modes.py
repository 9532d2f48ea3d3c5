"""Files socnavgen writes get ordinary modes: 0666 minus the umask, like any program's files."""

from __future__ import annotations

import os
import stat

import pytest

from socnavgen.safeio import atomic_write_text


@pytest.mark.parametrize("mask,expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_atomic_write_respects_umask(tmp_path, mask, expected):
    old = os.umask(mask)
    try:
        target = tmp_path / "out.yaml"
        atomic_write_text(target, "a: 1\n")
    finally:
        os.umask(old)
    assert stat.S_IMODE(target.stat().st_mode) == expected
    assert target.read_text() == "a: 1\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.yaml"]  # no temp file left behind


def test_every_exported_file_is_readable_by_others(make_run, tmp_path):
    from socnavgen.export import export_run

    from .export_helpers import REGULAR_TREE

    old = os.umask(0o022)
    try:
        out = tmp_path / "out"
        export_run(make_run(trees={"human1": REGULAR_TREE, "human2": REGULAR_TREE}), "hunav2", out, base="m")
    finally:
        os.umask(old)
    files = [p for p in out.rglob("*") if p.is_file()]
    assert len(files) >= 5
    assert {stat.S_IMODE(p.stat().st_mode) for p in files} == {0o644}
