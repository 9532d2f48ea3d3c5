"""`campaign report`: tables, plots and GIFs in one self-contained page and a markdown summary; the bad
policy comes out worst."""

from __future__ import annotations

import re

from socnavgen.campaign.aggregate import aggregate
from socnavgen.campaign.report import write_report
from socnavgen.campaign.runner import run_campaign
from socnavgen.campaign.store import read_episodes


def test_report_ranks_the_bad_policy_worst_and_is_self_contained(small_spec, tmp_path) -> None:  # noqa: ANN001
    out = tmp_path / "o"
    run_campaign(small_spec, out, executor="inline")
    agg = aggregate(read_episodes(out)[0], resamples=500, baseline="scripted")
    bad, good = agg.per_policy["bad"]["collisions"], agg.per_policy["scripted"]["collisions"]
    assert bad.mean > good.mean
    assert agg.paired["bad"]["collisions"].losses >= 3  # worse on most of the same scenario+seed pairs
    assert agg.worst[0]["policy"] == "bad"

    html_path, md_path = write_report(out, gifs=1, resamples=500, baseline="scripted")
    page = html_path.read_text()
    assert len(re.findall(r'src="data:image/png;base64,', page)) == 2  # bars + heatmap
    assert 'src="data:image/gif;base64,' in page  # the worst episode, rendered on demand
    assert not re.search(r'(src|href)="(http|//|/)', page)  # nothing outside the file
    for heading in ("Per policy", "Paired with scripted", "Success per scenario", "Worst episodes", "Metrics"):
        assert heading in page
    summary = md_path.read_text()
    assert "| bad |" in summary and "path_irregularity" in summary and "rad/m" in summary
    assert list((out / "report" / "gifs").glob("*bad*.gif"))
