"""The Ray executor, for real: a local cluster on 127.0.0.1 started by the test gives the same table."""

from __future__ import annotations

import pyarrow.parquet as pq
import pytest

from socnavgen.campaign.runner import run_campaign


def test_ray_local_cluster_gives_the_same_table(small_spec, tmp_path, monkeypatch) -> None:  # noqa: ANN001
    ray = pytest.importorskip("ray")
    monkeypatch.setenv("RAY_USAGE_STATS_ENABLED", "0")  # no network
    assert not ray.is_initialized()
    on_ray = run_campaign(small_spec, tmp_path / "ray", executor="ray", workers=2, batch_size=1)
    assert not ray.is_initialized()  # the cluster the campaign started is gone
    inline = run_campaign(small_spec, tmp_path / "inline", executor="inline")
    assert on_ray.total == inline.total == 8 and on_ray.failed == 0
    a = pq.read_table(tmp_path / "ray" / "episodes.parquet").drop(["wall_seconds"])
    b = pq.read_table(tmp_path / "inline" / "episodes.parquet").drop(["wall_seconds"])
    assert a.equals(b)
