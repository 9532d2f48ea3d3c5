"""Bootstrap CIs and paired differences: they separate what differs and not what does not."""

from __future__ import annotations

import numpy as np

from socnavgen.campaign.stats import bootstrap_mean, paired_difference


def test_ci_contains_the_mean_and_narrows_with_more_data() -> None:
    rng = np.random.default_rng(1)
    small = bootstrap_mean(rng.normal(5.0, 1.0, 20))
    large = bootstrap_mean(rng.normal(5.0, 1.0, 2000))
    assert small.low < small.mean < small.high
    assert large.low < 5.0 < large.high
    assert (large.high - large.low) < (small.high - small.low) / 3


def test_different_policies_do_not_overlap_and_equal_ones_do() -> None:
    rng = np.random.default_rng(2)
    good, bad = bootstrap_mean(rng.binomial(1, 0.9, 60)), bootstrap_mean(rng.binomial(1, 0.2, 60))
    assert not good.overlaps(bad)
    same = bootstrap_mean(rng.binomial(1, 0.9, 60))
    assert good.overlaps(same)


def test_undefined_values_are_left_out_and_seeded() -> None:
    x = np.array([1.0, np.nan, 3.0, np.inf])
    e = bootstrap_mean(x)
    assert e.n == 2 and e.mean == 2.0
    assert bootstrap_mean(x) == e  # same data, same CI
    assert bootstrap_mean(np.array([])).n == 0


def test_paired_difference_counts_wins_by_the_metric_direction() -> None:
    base = np.array([5.0, 5.0, 5.0, 5.0])
    mine = np.array([3.0, 4.0, 5.0, 9.0])
    lower = paired_difference(mine, base, "lower")
    assert (lower.wins, lower.ties, lower.losses) == (2, 1, 1)
    higher = paired_difference(mine, base, "higher")
    assert (higher.wins, higher.losses) == (1, 2)
    assert lower.difference.mean == 0.25
