"""Report figures as PNG bytes (inlined in the HTML page): policy x metric bars with CIs, and the
scenario x policy success heatmap."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from socnavgen.campaign.aggregate import Aggregates  # noqa: E402


def _png(fig: plt.Figure) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    plt.close(fig)
    return buf.getvalue()


def metric_bars(agg: Aggregates) -> bytes:
    metrics = agg.metrics
    cols = min(4, len(metrics))
    rows = int(np.ceil(len(metrics) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.6 * rows), squeeze=False)
    colors = plt.cm.tab10(np.arange(len(agg.policies)) % 10)
    for ax, metric in zip(axes.ravel(), metrics, strict=False):
        est = [agg.per_policy[p][metric] for p in agg.policies]
        means = np.array([e.mean for e in est])
        # a percentile CI need not contain the mean: bars never get a negative error length
        low = np.clip(np.nan_to_num(means - np.array([e.low for e in est])), 0.0, None)
        high = np.clip(np.nan_to_num(np.array([e.high for e in est]) - means), 0.0, None)
        ax.bar(range(len(est)), np.nan_to_num(means), yerr=[low, high], color=colors, capsize=4)
        ax.set_xticks(range(len(est)), agg.policies, rotation=30, ha="right", fontsize=8)
        ax.set_title(metric, fontsize=9)
    for ax in axes.ravel()[len(metrics):]:
        ax.axis("off")
    fig.suptitle("mean per policy, 95% bootstrap CI", fontsize=10)
    fig.tight_layout()
    return _png(fig)


def success_heatmap(agg: Aggregates) -> bytes:
    grid = np.array([[agg.per_scenario[(s, p)]["success"].mean for p in agg.policies] for s in agg.scenarios])
    fig, ax = plt.subplots(figsize=(1.2 + 1.1 * len(agg.policies), 0.8 + 0.28 * len(agg.scenarios)))
    image = ax.imshow(grid, vmin=0, vmax=1, cmap="RdYlGn", aspect="auto")
    ax.set_xticks(range(len(agg.policies)), agg.policies, rotation=30, ha="right", fontsize=8)
    ax.set_yticks(range(len(agg.scenarios)), agg.scenarios, fontsize=7)
    for (i, j), value in np.ndenumerate(grid):
        if np.isfinite(value):
            ax.text(j, i, f"{value:.2f}", ha="center", va="center", fontsize=6)
    fig.colorbar(image, ax=ax, label="success rate")
    ax.set_title("success per scenario and policy", fontsize=10)
    return _png(fig)
