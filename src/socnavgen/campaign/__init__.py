"""Campaigns: run robot policies over scenario suites x seeds (locally or on Ray), store one row per
episode in Parquet, and report aggregates with confidence intervals."""
