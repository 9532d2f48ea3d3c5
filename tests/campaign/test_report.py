"""`campaign report`: tables, plots and GIFs in one self-contained page and a markdown summary; the bad
policy comes out worst."""

from __future__ import annotations

import re

from socnavgen.campaign.aggregate import aggregate
from socnavgen.campaign.report import fit_markdown, md_tables, write_report
from socnavgen.campaign.runner import run_campaign
from socnavgen.campaign.store import read_episodes


def test_report_ranks_the_bad_policy_worst_and_is_self_contained(small_spec, tmp_path) -> None:  # noqa: ANN001
    out = tmp_path / "o"
    run_campaign(small_spec, out, executor="inline")
    agg = aggregate(read_episodes(out)[0], resamples=500, baseline="scripted")
    bad, good = agg.per_policy["bad"]["collisions"], agg.per_policy["scripted"]["collisions"]
    assert bad.mean > good.mean
    paired = agg.paired["bad"]["collisions"]  # worse on the blind corner's pairs, never better (people let it
    assert paired.losses >= 2 and paired.wins == 0  # drive across the open intersection: ties there)
    assert agg.worst[0]["policy"] == "bad"

    html_path, md_path, ranking_path = write_report(out, gifs=1, resamples=500, baseline="scripted")  # ReportFiles
    page = html_path.read_text()
    assert len(re.findall(r'src="data:image/png;base64,', page)) == 3  # ranking bars, TTC, success heatmap
    for name in ("ranking", "ttc", "success"):  # and each as vector figures beside the page, for papers
        assert (out / "report" / "figures" / f"{name}.svg").read_text().lstrip().startswith("<?xml")
        assert (out / "report" / "figures" / f"{name}.pdf").read_bytes().startswith(b"%PDF")
    assert re.search(r'src="data:image/gif;base64,[^"]+"></figure>|<figcaption>[^<]*bad', page)
    assert re.search(r"<figcaption>[^<]*policy bad, seed \d", page)  # the worst episode, rendered and captioned
    assert not re.search(r'(src|href)="(http|//|/)', page)  # nothing outside the file
    for heading in ("Per policy: the ranking", "Per location", "Expected behaviour per check", "Time to collision",
                    "Paired with scripted", "Success per scenario", "Worst episodes", "Metrics", "What a seed varies"):
        assert heading in page
    assert "Contact-free success" in page and "Time to goal (successes) (s)" in page  # readable names, units
    summary = md_path.read_text()
    assert re.search(r"^\| bad +\|", summary, re.M) and "path_irregularity" in summary and "rad/m" in summary
    assert max(map(len, summary.splitlines())) <= 100  # tables split to read in a terminal
    assert re.search(r"^\| bad +\|", ranking_path.read_text(), re.M)
    assert list((out / "report" / "gifs").glob("*bad*.gif"))


def test_wide_markdown_tables_split_to_80_columns_keeping_their_key_columns() -> None:
    header = ["Policy", *(f"Metric number {k}" for k in range(8))]
    rows = [["scripted", *(f"0.{k}1 [0.{k}0, 0.{k}2]" for k in range(8))], ["bad", *("–" for _ in range(8))]]
    text = md_tables(header, rows)
    tables = text.split("\n\n")
    assert len(tables) > 1 and all(len(line) <= 80 for line in text.splitlines())
    assert all(t.startswith("| Policy") and "| bad " in t for t in tables)  # the key column in every part
    assert sum(t.splitlines()[0].count("Metric number") for t in tables) == 8  # no column lost or repeated
    assert len(md_tables(header[:3], rows and [r[:3] for r in rows]).split("\n\n")) == 1  # narrow: one table


def test_the_printed_ranking_fits_the_terminal_it_is_asked_for_and_loses_no_cell() -> None:
    header = ["Policy", *(f"Metric number {k}" for k in range(9))]
    rows = [[name, *(f"0.{k}1 [0.{k}0, 0.{k}2]" for k in range(9))] for name in ("scripted", "a|b")]
    note = "1488 episodes: " + ", ".join(f"location_{k}" for k in range(30)) + "; mean [95 % bootstrap CI]."
    wide = md_tables(header, rows, width=10_000) + "\n\n" + note + "\n"
    assert fit_markdown(wide, 0) == wide  # the README's one wide table, as written
    for width in (80, 200):
        fitted = fit_markdown(wide, width)
        assert max(map(len, fitted.splitlines())) <= width
        tables = [b for b in fitted.split("\n\n") if b.startswith("|")]
        assert (len(tables) > 1) == (width == 80)
        assert all("| scripted " in t and "| a\\|b " in t for t in tables)  # the key column (escaped) in every part
        cells = " ".join(fitted.split())
        assert all(f"0.{k}1 [0.{k}0, 0.{k}2]" in cells for k in range(9)) and "location_29; mean" in cells
