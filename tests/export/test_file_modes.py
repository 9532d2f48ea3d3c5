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
