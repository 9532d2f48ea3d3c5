"""`campaign report OUT`: OUT/report/index.html (self-contained: images inlined), summary.md (tables split to
read in an 80-column terminal), the figures as PNG, SVG and PDF in OUT/report/figures/, and the README's ranking
table (`campaign report OUT --markdown`)."""

from __future__ import annotations

import base64
import html
import json
import re
import textwrap
from itertools import pairwise
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from socnavgen.campaign.aggregate import Aggregates, aggregate
from socnavgen.campaign.stats import Estimate
from socnavgen.campaign.store import read_episodes
from socnavgen.safeio import atomic_write_text
from socnavgen.sim.metric_definitions import label, metric_definitions

REPORT_DIR = "report"
RANKING_FILE = "ranking.md"  # the README's table (`campaign report OUT --markdown` prints it)
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
        done[row["episode"]] = write_gif(trace, location, out / REPORT_DIR / "gifs" / name, max_frames=150,
                                         width_in=6.0, dpi=100)
    return done


def _img(data: bytes, mime: str, alt: str, caption: str | None = None) -> str:
    img = f'<img alt="{html.escape(alt)}" src="data:{mime};base64,{base64.b64encode(data).decode()}">'
    return f"<figure>{img}<figcaption>{html.escape(caption)}</figcaption></figure>" if caption else img


def _table(header: list[str], rows: list[list[str]]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td class='{'wrap' if len(c) > 32 else 'num'}'>{html.escape(c)}</td>"
                                    for c in r) + "</tr>" for r in rows)
    return f"<div class='scroll'><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table></div>"


def _md_table(header: list[str], rows: list[list[str]]) -> str:
    esc = [[c.replace("|", "\\|") for c in r] for r in [header, *rows]]
    widths = [max(len(r[k]) for r in esc) for k in range(len(header))]
    lines = ["| " + " | ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)) + " |" for r in esc]
    lines.insert(1, "|" + "|".join("-" * (w + 2) for w in widths) + "|")
    return "\n".join(lines)


def md_tables(header: list[str], rows: list[list[str]], keys: int = 1, width: int = 80) -> str:
    """Markdown table(s) no wider than `width` columns where possible: a wide table is split by columns into
    several, each repeating the first `keys` columns (so summary.md reads in an 80-column terminal)."""
    cells = [header, *rows]

    def w(k: int) -> int:
        return max(len(r[k]) for r in cells) + 3

    base = sum(w(k) for k in range(keys)) + 1
    groups: list[list[int]] = [[]]
    used = base
    for k in range(keys, len(header)):
        if groups[-1] and used + w(k) > width:
            groups.append([])
            used = base
        groups[-1].append(k)
        used += w(k)
    parts = []
    for group in groups:
        chosen = [*range(keys), *group]
        parts.append(_md_table([header[k] for k in chosen], [[r[k] for k in chosen] for r in rows]))
    return "\n\n".join(parts)


def _wrap(text: str, width: int = 80) -> str:
    return textwrap.fill(text, width, break_long_words=False, break_on_hyphens=False)


def md_glossary(rows: list[list[str]]) -> str:
    """The metric definitions as a list wrapped at 80 columns (a table of prose does not fit a terminal)."""
    items = []
    for name, column, unit, meaning, formula in rows:
        text = f"- **{name}** (`{column}`, {unit or 'no unit'}): {meaning}" + (f". Formula: {formula}" if formula
                                                                              else "")
        items.append(textwrap.fill(text, 80, subsequent_indent="  ", break_long_words=False,
                                   break_on_hyphens=False))
    return "\n".join(items)


def md_list(header: list[str], rows: list[list[str]]) -> str:
    """A table whose last column is prose, as a list wrapped at 80 columns: '- A, B: c; D: d. Last'."""
    if not rows:
        return "None."
    items = [f"- {r[0]}, {r[1]}, " + "; ".join(f"{h.lower()} {c}" for h, c in zip(header[2:-1], r[2:-1],
                                                                                   strict=True)) + f": {r[-1]}"
             for r in rows]
    return "\n".join(textwrap.fill(i, 80, subsequent_indent="  ", break_long_words=False, break_on_hyphens=False)
                     for i in items)


def cell(estimate: Estimate, metric: str) -> str:
    """'0.52 [0.46, 0.57]': the mean and its 95 % CI, with as many decimals as the metric's unit needs."""
    if estimate.n == 0 or not np.isfinite(estimate.mean):
        return "–"
    unit = metric_definitions([metric])[metric]["unit"] if metric != "check" else "bool"
    fmt = "{:.2f}" if unit in ("bool", "1") else "{:.1f}" if unit == "s" else "{:.3g}"
    return f"{fmt.format(estimate.mean)} [{fmt.format(estimate.low)}, {fmt.format(estimate.high)}]"


def head(metric: str) -> str:
    return label(metric, unit=True)


Section = tuple[str, list[str], list[list[str]], int]  # title, header, rows, key columns (kept when split)


def _ranking(agg: Aggregates) -> Section:
    rows = [[p, str(agg.per_policy[p]["success"].n), str(agg.failed[p])]
            + [cell(agg.per_policy[p][m], m) for m in agg.ranking] for p in agg.policies]
    return (f"Per policy: the ranking (mean [95 % bootstrap CI] over {agg.episodes} episodes, {agg.seeds} seeds "
            "per scenario; best first)", ["Policy", "Episodes", "Crashed", *(head(m) for m in agg.ranking)], rows, 1)


def _sections(agg: Aggregates) -> list[Section]:
    """Every table, shared by the HTML page and the markdown summary."""
    secondary = [m for m in agg.metrics if m not in agg.ranking]
    comfort = [[p, cell(agg.verified[p], "success")] + [cell(agg.per_policy[p][m], m) for m in secondary]
               for p in agg.policies]
    location_rows = [[loc, p] + [cell(agg.per_location[(loc, p)][m], m) for m in agg.ranking]
                     for loc in agg.locations for p in agg.policies]
    from socnavgen.sim.behaviour_checks import check_title

    checks = sorted({c for c, _ in agg.checks}, key=check_title)
    check_rows = [[check_title(c), _applied(agg, c)] + [cell(agg.checks[(c, p)], "check") if (c, p) in agg.checks else "–"
                                           for p in agg.policies] for c in checks]
    ttc_rows = [[p] + [f"{v / max(1, agg.per_policy[p]['success'].n):.2f}" for v in agg.ttc[p]]
                for p in agg.policies if p in agg.ttc]
    paired_metrics = [m for m in (*agg.ranking, "collisions") if m in agg.metrics]
    paired_rows = [[p, label(m), cell(agg.paired[p][m].difference, m), str(agg.paired[p][m].wins),
                    str(agg.paired[p][m].ties), str(agg.paired[p][m].losses)]
                   for p in agg.paired for m in paired_metrics]
    scenario_rows = [[s] + [cell(agg.per_scenario[(s, p)]["success"], "success") for p in agg.policies]
                     for s in sorted(agg.scenarios, key=lambda s: (agg.scenario_location.get(s, ""), s))]
    worst_rows = [[r["scenario"], r["policy"], str(r["seed"]), r.get("end_reason") or r["status"],
                   str(r.get("collisions")),
                   f"{r['minimum_distance_to_people']:.2f}" if r.get("minimum_distance_to_people") is not None else "–",
                   r.get("failure_reason") or ""] for r in agg.worst]
    return [
        _ranking(agg),
        ("Per policy: safety and comfort", ["Policy", "Verified", *(head(m) for m in secondary)], comfort, 1),
        ("Per location (the ranking's metrics)", ["Location", "Policy", *(head(m) for m in agg.ranking)],
         location_rows, 2),
        ("Expected behaviour per check (pass rate where the check applied)", ["Check", "Applied in", *agg.policies],
         check_rows, 2),
        ("Time to collision: seconds per episode in each bin", ["Policy", *_ttc_bins()], ttc_rows, 1),
        (f"Paired with {agg.baseline} (same scenarios and seeds; difference = policy - {agg.baseline})",
         ["Policy", "Metric", "Mean difference [95 % CI]", "Better", "Same", "Worse"], paired_rows, 2),
        ("Success per scenario (contact-free success rate [95 % CI])", ["Scenario", *agg.policies],
         scenario_rows, 1),
        ("Worst episodes (failures only, worst first)",
         ["Scenario", "Policy", "Seed", "End", "Contact steps", "Min gap (m)", "Why"], worst_rows, 3),
        ("Metrics", ["Metric", "Column", "Unit", "Meaning", "Formula"], _glossary(agg, checks), 2),
    ]


def _applied(agg: Aggregates, check: str) -> str:
    """How many episodes per policy the check applied in: '600' or '141-152'."""
    counts = sorted({agg.checks[(check, p)].n for p in agg.policies if (check, p) in agg.checks})
    return f"{counts[0]}" if len(counts) == 1 else f"{counts[0]}-{counts[-1]}"


def _ttc_bins() -> list[str]:
    from socnavgen.sim.social_metrics import TTC_EDGES

    return [f"{a:g}-{b:g} s" if np.isfinite(b) else f">= {a:g} s" for a, b in pairwise(TTC_EDGES)]


def _glossary(agg: Aggregates, checks: list[str]) -> list[list[str]]:
    from socnavgen.sim.behaviour_checks import CHECKS, check_title

    names = [*agg.metrics, *(n for n in NAVIGATION if n not in agg.metrics)]
    definitions = metric_definitions(names)
    rows = [[label(m), m, d["unit"], d["meaning"], d.get("formula") or ""] for m, d in definitions.items()]
    return rows + [[f"Check: {check_title(c)}", f"expected_checks: {c}", "bool", CHECKS[c][1] if c in CHECKS else "", ""]
                   for c in checks]


def seed_note(agg: Aggregates) -> str:
    """What a seed varies (campaign/variation.py), and what this campaign's people drew."""
    from socnavgen.campaign.variation import APPLIED, DISTRIBUTIONS

    applied = [DISTRIBUTIONS[k] for k in (*APPLIED, "spawn")]
    waiting = [k.replace("_", " ") for k in DISTRIBUTIONS if k not in APPLIED and k != "spawn"]
    drawn = (f" Walking speeds drawn here: {agg.speeds[0]:.2f}-{agg.speeds[1]:.2f} m/s." if agg.speeds else "")
    later = (f" Also drawn and recorded per person, not yet taken by the simulator: {', '.join(waiting)}."
             if waiting else "")
    return ("What a seed varies: each person's " + "; ".join(applied) + "." + drawn + later +
            " The same seed gives the same people to every policy, so paired comparisons compare like with like.")


CSS = ("body{font-family:system-ui,sans-serif;max-width:1400px;margin:1em auto;padding:0 1em;color:#111}"
       "table{border-collapse:collapse;font-size:13px;margin-bottom:1.2em}"
       "td,th{border:1px solid #ccc;padding:3px 7px;text-align:left;vertical-align:top}"
       "th{background:#eef1f5}tbody tr:nth-child(even){background:#fafafa}.scroll{overflow-x:auto}"
       "td.num{white-space:nowrap}img{max-width:100%}figure{display:inline-block;margin:4px;vertical-align:top}"
       ".gifs figure{width:calc(50% - 12px);max-width:640px}.gifs img{width:100%}"
       "figcaption{font-size:13px;color:#333}.note{background:#fff3cd;padding:6px}.seed{background:#eef6ee;"
       "padding:6px}")


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


def ranking_markdown(agg: Aggregates) -> str:
    """The README's table: the ranking per policy with CIs, and one line saying what it was measured on."""
    title, header, rows, _ = _ranking(agg)
    return (f"{_md_table(header, rows)}\n\n{agg.episodes} episodes: {len(agg.scenarios)} scenarios "
            f"({', '.join(agg.locations)}) x {len(agg.policies)} policies x {agg.seeds} seeds; mean [95 % bootstrap "
            "CI]; contact-free success = the goal reached touching no person and no wall; time to goal over "
            "contact-free successes only; path efficiency = shortest walkable path / path driven, over episodes that "
            "reached the goal.")


def fit_markdown(text: str, width: int) -> str:
    """Markdown of tables and paragraphs re-flowed for a terminal `width` columns wide: each table split by
    columns (the first column repeated, as in summary.md), each paragraph wrapped. 0 keeps it as written
    (the README wants the ranking as one wide table)."""
    if width <= 0:
        return text
    blocks = []
    for block in text.strip("\n").split("\n\n"):
        lines = block.splitlines()
        if lines and all(line.startswith("|") for line in lines) and len(lines) >= 2:
            cells = [[c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line)[1:-1]]
                     for line in lines if not set(line) <= set("|-: ")]
            blocks.append(md_tables(cells[0], cells[1:], keys=1, width=width))
        else:
            blocks.append(_wrap(" ".join(lines), width))
    return "\n\n".join(blocks) + "\n"


def _figures(agg: Aggregates, folder: Path) -> list[tuple[int, str, bytes, str]]:
    """(section index it follows, alt text, PNG bytes, caption) of each figure; SVG and PDF written beside."""
    from socnavgen.campaign.plots import metric_bars, save, success_heatmap, ttc_chart

    out = [(0, "policy x metric bars with 95% CIs", save(metric_bars(agg), folder, "ranking"),
            "The ranking's metrics per policy: mean and 95 % bootstrap CI (figures/ranking.svg, .pdf).")]
    ttc = ttc_chart(agg, _ttc_bins())
    if ttc is not None:
        out.append((4, "time-to-collision distribution per policy", save(ttc, folder, "ttc"),
                    "Seconds per episode with a contact less than the bin's time ahead (figures/ttc.svg, .pdf)."))
    if "success" in agg.metrics:
        out.append((6, "scenario x policy success heatmap", save(success_heatmap(agg), folder, "success"),
                    "Contact-free success rate per scenario and policy (figures/success.svg, .pdf)."))
    return out


def _caption(row: dict[str, Any]) -> str:
    why = row.get("failure_reason") or row.get("end_reason") or row["status"]
    return f"{row['scenario']}, policy {row['policy']}, seed {row['seed']}: {why}"


class ReportFiles(NamedTuple):
    """What `write_report` wrote, by name (iterable, so callers may list them)."""

    html: Path  # the self-contained page
    summary: Path  # summary.md
    ranking: Path  # the ranking table alone (`campaign report --markdown`)


def write_report(out: Path | str, *, gifs: int = 3, resamples: int = 2000, baseline: str | None = None,
                 notes: list[str] | None = None) -> ReportFiles:
    """Write the report; `notes` (if given) receives what the reader must know (an unfinished campaign,
    unreadable files), which the page and the summary also show at the top."""
    out = Path(out)
    table, found = campaign_table(out)
    if notes is not None:
        notes.extend(found)
    agg = aggregate(table, resamples=resamples, baseline=baseline, worst=max(10, 4 * gifs))
    report = out / REPORT_DIR
    sections = _sections(agg)
    figures = _figures(agg, report / "figures")
    # GIFs of different (scenario, policy) pairs, the worst of each: eight seeds of one failure show nothing new
    shown = list({(r["scenario"], r["policy"]): r for r in reversed(agg.worst)}.values())[::-1][:gifs]
    rendered = render_gifs(out, shown) if gifs else {}
    captions = {r["episode"]: _caption(r) for r in shown}
    title = f"Campaign report: {out.name} ({agg.episodes} episodes, {len(agg.policies)} policies, " \
            f"{len(agg.scenarios)} scenarios, {agg.seeds} seeds)"
    seeds = seed_note(agg)
    parts = [f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
             f"<style>{CSS}</style></head><body><h1>{html.escape(title)}</h1>"]
    parts += [f"<p class='note'><b>Note:</b> {html.escape(n)}</p>" for n in found]
    parts.append(f"<p class='seed'>{html.escape(seeds)}</p>")
    for k, (heading, header, rows, _) in enumerate(sections):
        parts.append(f"<h2>{html.escape(heading)}</h2>")
        parts.append(_table(header, rows) if rows else "<p>None.</p>")
        parts += [_img(data, "image/png", alt, caption) for at, alt, data, caption in figures if at == k]
        if heading.startswith("Worst episodes") and rendered:
            parts.append("<div class='gifs'>" + "".join(
                _img(path.read_bytes(), "image/gif", key, captions.get(key)) for key, path in rendered.items())
                + "</div>")
    parts.append("</body></html>")
    atomic_write_text(report / "index.html", "\n".join(parts))
    md = [f"# {title}", "", *(f"> **Note:** {n}\n" for n in found), _wrap(seeds), ""]
    for heading, header, rows, keys in sections:
        body = (md_glossary(rows) if heading == "Metrics" else md_list(header, rows) if heading.startswith("Worst")
                else md_tables(header, rows, keys) if rows else "None.")
        md += [_wrap(f"## {heading}"), "", body, ""]
    if rendered:
        md += ["GIFs of the worst episodes:", "", *(textwrap.fill(f"- [{captions.get(k, k)}](gifs/{p.name})", 80,
                                                                subsequent_indent="  ", break_long_words=False,
                                                                break_on_hyphens=False)
                                                  for k, p in rendered.items()), ""]
    md += [_wrap("Figures (PNG, SVG, PDF): " + ", ".join(f"figures/{n}.svg" for n in ("ranking", "ttc", "success")
                                                         if (report / "figures" / f"{n}.svg").is_file())), ""]
    atomic_write_text(report / "summary.md", "\n".join(md))
    atomic_write_text(report / RANKING_FILE, ranking_markdown(agg) + "\n")
    return ReportFiles(report / "index.html", report / "summary.md", report / RANKING_FILE)
