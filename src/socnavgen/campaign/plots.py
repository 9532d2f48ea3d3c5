"""Report figures: the ranking metrics per policy with their CIs, the scenario x policy success heatmap (grouped
by location) and the time-to-collision distribution. Each is a matplotlib Figure; `save` writes it as PNG (inlined
in the HTML page) and as SVG and PDF beside the report (for papers), readable at a paper's width."""

from __future__ import annotations

import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from socnavgen.campaign.aggregate import Aggregates  # noqa: E402
from socnavgen.safeio import atomic_write_bytes  # noqa: E402
from socnavgen.sim.metric_definitions import label  # noqa: E402

FORMATS = ("png", "svg", "pdf")
FONT = 9  # pt: the smallest text of a figure 7 in wide (a paper's full width)


def axis_label(metric: str) -> str:
    """'Time to goal (successes) (s)': the readable name and its unit (none for rates and ratios)."""
    return label(metric, unit=True)


def save(fig: plt.Figure, folder: Path, name: str) -> bytes:
    """Write FOLDER/NAME.{png,svg,pdf}; return the PNG bytes (what the page inlines)."""
    png = b""
    try:
        for fmt in FORMATS:
            buf = io.BytesIO()
            fig.savefig(buf, format=fmt, dpi=110, bbox_inches="tight",
                        metadata={"Date": None} if fmt in ("svg", "pdf") else None)
            atomic_write_bytes(folder / f"{name}.{fmt}", buf.getvalue())
            png = buf.getvalue() if fmt == "png" else png
    finally:
        plt.close(fig)
    return png


def _colors(n: int) -> np.ndarray:
    return plt.cm.tab10(np.arange(n) % 10)


def metric_bars(agg: Aggregates) -> plt.Figure:
    """One panel per ranking metric: each policy's mean with its 95 % CI, policies in ranking order."""
    metrics = agg.ranking or agg.metrics[:6]
    cols = min(3, len(metrics))
    rows = int(np.ceil(len(metrics) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(7.0, 0.6 + (0.9 + 0.22 * len(agg.policies)) * rows),
                             squeeze=False)
    y = np.arange(len(agg.policies))
    for ax, metric in zip(axes.ravel(), metrics, strict=False):
        est = [agg.per_policy[p][metric] for p in agg.policies]
        means = np.array([e.mean for e in est])
        # a percentile CI need not contain the mean: bars never get a negative error length
        low = np.clip(np.nan_to_num(means - np.array([e.low for e in est])), 0.0, None)
        high = np.clip(np.nan_to_num(np.array([e.high for e in est]) - means), 0.0, None)
        ax.barh(y, np.nan_to_num(means), xerr=[low, high], color=_colors(len(est)), capsize=3)
        for k, e in enumerate(est):
            if e.n == 0:
                ax.text(0, k, " no data", va="center", fontsize=FONT - 1, color="#555")
        ax.set_yticks(y, agg.policies, fontsize=FONT)
        ax.invert_yaxis()  # the best policy on top
        ax.tick_params(axis="x", labelsize=FONT - 1)
        ax.set_title(axis_label(metric), fontsize=FONT)
    for ax in axes.ravel()[len(metrics):]:
        ax.axis("off")
    fig.suptitle(f"Mean per policy with 95 % bootstrap CI ({agg.episodes} episodes)", fontsize=FONT + 1)
    fig.tight_layout()
    return fig


def _text_color(rgba: tuple[float, ...]) -> str:
    """Black on light cells, white on dark ones (relative luminance, WCAG)."""
    r, g, b = (c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4 for c in rgba[:3])
    return "black" if 0.2126 * r + 0.7152 * g + 0.0722 * b > 0.18 else "white"


def success_heatmap(agg: Aggregates, metric: str = "success") -> plt.Figure:
    """Scenario x policy rate of `metric`, scenarios grouped by location (a line between locations)."""
    scenarios = sorted(agg.scenarios, key=lambda s: (agg.scenario_location.get(s, ""), s))
    grid = np.array([[agg.per_scenario[(s, p)][metric].mean if metric in agg.per_scenario[(s, p)] else np.nan
                      for p in agg.policies] for s in scenarios], dtype=float).reshape(len(scenarios), -1)
    cmap = plt.get_cmap("RdYlBu")
    fig, ax = plt.subplots(figsize=(min(7.0, 3.2 + 0.9 * len(agg.policies)), 1.2 + 0.2 * len(scenarios)))
    image = ax.imshow(grid, vmin=0, vmax=1, cmap=cmap, aspect="auto")
    ax.set_xticks(range(len(agg.policies)), agg.policies, fontsize=FONT)
    ax.xaxis.tick_top()
    ax.set_yticks(range(len(scenarios)), scenarios, fontsize=FONT - 2)
    for (i, j), value in np.ndenumerate(grid):
        if np.isfinite(value):
            ax.text(j, i, f"{value:.2f}", ha="center", va="center", fontsize=FONT - 2,
                    color=_text_color(cmap(value)))
    locations = [agg.scenario_location.get(s, "") for s in scenarios]
    for i in range(1, len(scenarios)):
        if locations[i] != locations[i - 1]:
            ax.axhline(i - 0.5, color="black", lw=1.2)
    fig.colorbar(image, ax=ax, label=axis_label(metric), fraction=0.05, pad=0.02)
    ax.set_title(f"{label(metric)} per scenario and policy (scenarios grouped by location)", fontsize=FONT)
    return fig


def ttc_chart(agg: Aggregates, names: list[str]) -> plt.Figure | None:
    """Seconds per episode with the smallest time to collision in each bin, stacked per policy (the short-TTC
    bins first); None when the table has no TTC column."""
    policies = [p for p in agg.policies if p in agg.ttc]
    if not policies:
        return None
    per_episode = {p: np.asarray(agg.ttc[p]) / max(1, agg.per_policy[p]["success"].n if "success" in
                                                   agg.per_policy[p] else 1) for p in policies}
    shown = len(names) - 1  # the last bin ("never") dwarfs the others: it is in the table, not the figure
    fig, ax = plt.subplots(figsize=(7.0, 0.9 + 0.3 * len(policies)))
    left = np.zeros(len(policies))
    colors = plt.cm.Reds_r(np.linspace(0.1, 0.8, shown))
    for k in range(shown):
        values = np.array([per_episode[p][k] for p in policies])
        ax.barh(policies, values, left=left, color=colors[k], label=names[k])
        left += values
    ax.invert_yaxis()
    ax.set_xlabel("seconds per episode with the smallest time to collision in the bin", fontsize=FONT)
    ax.tick_params(labelsize=FONT)
    ax.legend(fontsize=FONT - 1, loc="center left", bbox_to_anchor=(1.01, 0.5), title="smallest TTC",
              title_fontsize=FONT - 1)
    ax.set_title("Time to collision (constant velocities)", fontsize=FONT)
    return fig
