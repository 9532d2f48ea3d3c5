"""`campaign report OUT`: OUT/report/index.html (self-contained: images inlined) and summary.md."""

from __future__ import annotations

import base64
import html
import json
from pathlib import Path
from typing import Any

from socnavgen.campaign.aggregate import Aggregates, aggregate
from socnavgen.campaign.store import read_episodes
from socnavgen.safeio import atomic_write_text
from socnavgen.sim.metric_definitions import metric_definitions

REPORT_DIR = "report"
NAVIGATION = ("path_irregularity", "path_efficiency", "static_obstacle_collisions", "min_obstacle_clearance")


def render_gifs(out: Path, rows: list[dict[str, Any]]) -> dict[str, Path]:
    """Re-simulate the given episodes (deterministic: same seed, same trace) and write their GIFs."""
    from socnavgen.campaign.episode import Episode, WorkerCache, simulate_episode
    from socnavgen.campaign.runner import CAMPAIGN_FILE, SCENARIOS_FILE, settings_of
    from socnavgen.campaign.scenarios import Scenario
    from socnavgen.campaign.spec import CampaignSpec
    from socnavgen.sim.outputs.animate import write_gif

    spec = CampaignSpec.model_validate_json((out / CAMPAIGN_FILE).read_text())
    scenarios = {s["id"]: Scenario(**s) for s in json.loads((out / SCENARIOS_FILE).read_text())["scenarios"]}
    robots = {p.name: p.robot for p in spec.policies}
    params = {p.name: tuple(sorted(p.params.items())) for p in spec.policies}
    settings, cache, done = settings_of(spec), WorkerCache(), {}
    for row in rows:
        if row["scenario"] not in scenarios or row["policy"] not in robots:
            continue
        ep = Episode(scenarios[row["scenario"]], row["policy"], robots[row["policy"]], int(row["seed"]),
                     params=params[row["policy"]])
        try:
            trace, location, _ = simulate_episode(ep, settings, cache)
        except Exception:  # noqa: BLE001, S112 - the crash is already the episode's recorded failure
            continue
        name = "".join(c if c.isalnum() or c in "-_" else "_" for c in ep.key) + ".gif"
        done[row["episode"]] = write_gif(trace, location, out / REPORT_DIR / "gifs" / name, max_frames=120,
                                         width_in=4.5, dpi=70)
    return done


def _img(data: bytes, mime: str, alt: str) -> str:
    return f'<img alt="{html.escape(alt)}" src="data:{mime};base64,{base64.b64encode(data).decode()}">'


def _table(header: list[str], rows: list[list[str]]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _md_table(header: list[str], rows: list[list[str]]) -> str:
    esc = [[c.replace("|", "\\|") for c in r] for r in rows]
    return "\n".join(["| " + " | ".join(header) + " |", "|" + "---|" * len(header),
                      *("| " + " | ".join(r) + " |" for r in esc)])


def _sections(agg: Aggregates) -> list[tuple[str, list[str], list[list[str]]]]:
    """(title, header, rows) of every table, shared by the HTML page and the markdown summary."""
    policy_rows = [[p, str(agg.per_policy[p][agg.metrics[0]].n), str(agg.failed[p]), agg.verified[p].text()]
                   + [agg.per_policy[p][m].text() for m in agg.metrics] for p in agg.policies]
    paired_rows = [[p, m, agg.paired[p][m].difference.text(), str(agg.paired[p][m].wins), str(agg.paired[p][m].ties),
                    str(agg.paired[p][m].losses)] for p in agg.paired for m in agg.metrics]
    scenario_rows = [[s] + [agg.per_scenario[(s, p)]["success"].text(2) for p in agg.policies]
                     for s in agg.scenarios]
    worst_rows = [[r["scenario"], r["policy"], str(r["seed"]), r["status"], str(r.get("collisions")),
                   f"{r['minimum_distance_to_people']:.2f}" if r.get("minimum_distance_to_people") is not None else "–",
                   r.get("failure_reason") or ""] for r in agg.worst]
    definitions = metric_definitions()
    glossary = [[m, definitions[m]["unit"], definitions[m].get("formula", ""), definitions[m]["meaning"]]
                for m in [*agg.metrics, *(n for n in NAVIGATION if n not in agg.metrics)] if m in definitions]
    return [
        ("Per policy (mean [95% bootstrap CI])", ["policy", "episodes", "crashed/timed out", "verified"] + agg.metrics,
         policy_rows),
        (f"Paired with {agg.baseline} (same scenarios and seeds; difference = policy - {agg.baseline})",
         ["policy", "metric", "mean difference [95% CI]", "better", "same", "worse"], paired_rows),
        ("Success per scenario (rate [95% CI])", ["scenario", *agg.policies], scenario_rows),
        ("Worst episodes", ["scenario", "policy", "seed", "status", "collisions", "min gap (m)", "why"], worst_rows),
        ("Metrics", ["metric", "unit", "formula", "meaning"], glossary),
    ]


CSS = ("body{font-family:sans-serif;max-width:1200px;margin:1em auto}table{border-collapse:collapse;font-size:12px;"
       "margin-bottom:1.5em}td,th{border:1px solid #ccc;padding:2px 6px;text-align:left}img{max-width:100%}"
       ".gifs img{width:32%;margin:2px}.note{background:#fff3cd;padding:6px}")


def campaign_table(out: Path) -> tuple[Any, list[str]]:
    """(the episode table, notes for the reader): episodes.parquet of a finished campaign; for one that was
    stopped, the rows of its current episodes found in parts/, with a note saying it is unfinished."""
    from socnavgen.campaign.fingerprint import read_inputs
    from socnavgen.campaign.runner import CAMPAIGN_FILE, SCENARIOS_FILE
    from socnavgen.campaign.store import TABLE

    plan = None
    inputs = read_inputs(out)
    try:
        campaign = json.loads((out / CAMPAIGN_FILE).read_text())
        scenarios = [s["id"] for s in json.loads((out / SCENARIOS_FILE).read_text())["scenarios"]]
        if inputs is not None:
            plan = inputs.plan(scenarios, [p["name"] for p in campaign["policies"]], campaign["seeds"])
    except (OSError, ValueError, KeyError, TypeError):
        pass  # a folder from an older socnavgen: report what is there
    finished = (out / TABLE).is_file()
    table, notes = read_episodes(out, plan)  # the plan chooses rows only when they come from the parts
    if table.num_rows == 0:
        from socnavgen.errors import InputFileError

        raise InputFileError("no episode of this campaign has a row yet", file=out,
                             hint="run (or finish) it with `socnavgen campaign run FILE -o OUT`")
    if not finished:
        total = f" of {len(plan)}" if plan is not None else ""
        notes.insert(0, f"unfinished campaign: {table.num_rows}{total} episodes have a row (it was stopped before "
                        "the end); run the same `socnavgen campaign run` command again to finish it")
    return table, notes


def write_report(out: Path | str, *, gifs: int = 3, resamples: int = 2000, baseline: str | None = None,
                 notes: list[str] | None = None) -> list[Path]:
    """Write the report; `notes` (if given) receives what the reader must know (an unfinished campaign,
    unreadable files), which the page and the summary also show at the top."""
    from socnavgen.campaign.plots import metric_bars, success_heatmap

    out = Path(out)
    table, found = campaign_table(out)
    if notes is not None:
        notes.extend(found)
    agg = aggregate(table, resamples=resamples, baseline=baseline)
    sections = _sections(agg)
    rendered = render_gifs(out, agg.worst[:gifs]) if gifs else {}
    title = f"Campaign report: {out.name} ({agg.episodes} episodes, {len(agg.policies)} policies, " \
            f"{len(agg.scenarios)} scenarios)"
    parts = [f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
             f"<style>{CSS}</style></head><body><h1>{html.escape(title)}</h1>"]
    parts += [f"<p class='note'><b>Note:</b> {html.escape(n)}</p>" for n in found]
    for k, (heading, header, rows) in enumerate(sections):
        parts.append(f"<h2>{html.escape(heading)}</h2>{_table(header, rows)}")
        if k == 0:
            parts.append(_img(metric_bars(agg), "image/png", "policy x metric bars with 95% CIs"))
        if k == 2:
            parts.append(_img(success_heatmap(agg), "image/png", "scenario x policy success heatmap"))
        if k == 3 and rendered:
            parts.append("<div class='gifs'>" + "".join(_img(path.read_bytes(), "image/gif", key)
                                                        for key, path in rendered.items()) + "</div>")
    parts.append("</body></html>")
    report = out / REPORT_DIR
    atomic_write_text(report / "index.html", "\n".join(parts))
    md = [f"# {title}", "", *(f"> **Note:** {n}\n" for n in found)]
    for heading, header, rows in sections:
        md += [f"## {heading}", "", _md_table(header, rows), ""]
    if rendered:
        md += ["GIFs of the worst episodes: " + ", ".join(f"[{k}](gifs/{p.name})" for k, p in rendered.items()), ""]
    atomic_write_text(report / "summary.md", "\n".join(md))
    return [report / "index.html", report / "summary.md"]
