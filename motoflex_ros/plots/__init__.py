"""Plots (matplotlib, Agg backend), imported lazily by the CLI verbs; never by the core."""
