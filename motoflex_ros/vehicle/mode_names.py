"""The names of the motorcycle's tracked modes, for every layer that loops over them.

:mod:`.modes` finds them by frequency band and mode shape; the studies, figures, recordings and
the CLI read their results by these names. A module of its own so that the launcher, the
figures and the CLI take the names without :mod:`.modes`'s scipy.
"""
__all__ = ["STUDIED_MODES", "MODE_NAMES"]

STUDIED_MODES = ("weave", "wobble")
"""The two oscillating modes of the paper's studies: e_RMS (eq. 18), stability index
(eqs. 13-15), Pearson coefficients (eqs. 16-17), Figs. 7-10."""
MODE_NAMES = (*STUDIED_MODES, "capsize")
"""Every mode :func:`.modes.modal_sweep` tracks (capsize: real, not studied by the paper)."""
