"""Figures (matplotlib, Agg backend). Imported lazily by the CLI verbs; the core never imports
this package."""
