"""Plots of the studies (Passigato et al. 2023): Fig. 10 Pearson bars, Fig. 8 e_RMS bars and
Fig. 4-style stability-index curves. PNG files, written atomically."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.plots.labels import QUANTITY_LABELS, VARIANT_LABELS  # noqa: E402
from motoflex_ros.plots.vehicle import save_png  # noqa: E402
from motoflex_ros.study.stability_index import RANGE_NAMES  # noqa: E402
from motoflex_ros.units import ms_to_kmh  # noqa: E402
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["plot_pearson_bars", "plot_accuracy_bars", "plot_stability_curves",
           "pearson_bars_figure", "accuracy_bars_figure"]

FLOOR_PCT, CEILING_PCT = 1e-3, 300.0
"""Range of the e_RMS axis [%]: bars below the floor show as the floor with their value."""

_RANGE_LABELS = {"low": "40-100 km/h", "high": "100-210 km/h"}
_FACTOR_LABELS = {"k_tf": "$k_{tf}$", "k_bf": "$k_{bf}$", "k_ta": "$k_{ta}$",
                  "k_ba": "$k_{ba}$", "k_ts": "$k_{ts}$", "k_bs": "$k_{bs}$"}


def _grouped_bars(ax, groups, series, zero_line=True):
    """Bars of several series side by side over the groups; series: {label: values}; returns
    the bar containers."""
    width = 0.8 / max(len(series), 1)
    x = np.arange(len(groups))
    containers = [ax.bar(x + (i - (len(series) - 1) / 2) * width, values, width, label=label)
                  for i, (label, values) in enumerate(series.items())]
    ax.set_xticks(x, groups)
    if zero_line:
        ax.axhline(0.0, color="black", linewidth=0.8)
    ax.grid(axis="y", alpha=0.3)
    return containers


def pearson_bars_figure(pearson, modes=STUDIED_MODES, ranges=RANGE_NAMES):
    """Fig. 10: Pearson coefficient of every stiffness with the weave and wobble indices.

    ``pearson`` is {"<mode>_<range>": {factor: rho}} as from
    :func:`motoflex_ros.study.correlation.pearson_table`; returns the matplotlib Figure.
    """
    fig, axes = plt.subplots(1, len(modes), figsize=(10, 4), sharey=True, layout="constrained")
    for ax, mode in zip(np.atleast_1d(axes), modes):
        factors = list(pearson[f"{mode}_{ranges[0]}"])
        series = {_RANGE_LABELS.get(r, r): [pearson[f"{mode}_{r}"][f] for f in factors]
                  for r in ranges}
        _grouped_bars(ax, [_FACTOR_LABELS.get(f, f) for f in factors], series)
        ax.set_title(mode.capitalize())
        ax.set_ylim(-1.05, 1.05)
        ax.legend()
    np.atleast_1d(axes)[0].set_ylabel(r"Pearson coefficient $\rho_{IF}$ [-]")
    fig.suptitle("Stiffness up: positive = more damping of the mode (Fig. 10)")
    return fig


def plot_pearson_bars(pearson, path, modes=STUDIED_MODES, ranges=RANGE_NAMES):
    """Write :func:`pearson_bars_figure` as PNG to ``path``; returns the path."""
    return save_png(pearson_bars_figure(pearson, modes, ranges), path)


BAR_PITCH_IN = 0.14
"""Height of one horizontal bar of Fig. 8 with its gap [in]: room for a value label of
:data:`BAR_LABEL_PT` beside it."""
BAR_LABEL_PT = 7.5
"""Size of the value written beside each bar [pt]: 10.4 px at the report's 100 dpi."""


def _label_bars(ax, bars):
    for bar in bars:
        value = bar.get_width()
        ax.annotate(f"{value:.2g}", (max(value, FLOOR_PCT), bar.get_y() + bar.get_height() / 2),
                    xytext=(2, 0), textcoords="offset points", ha="left", va="center",
                    fontsize=BAR_LABEL_PT)


def accuracy_bars_figure(errors):
    """Fig. 8: e_RMS% (eq. 18) of each lumped variant, per case (frame, ..., all), as
    horizontal bars on a log axis (errors from 0.01 % to 100 % side by side) with each bar's
    value written beside it, horizontally.

    ``errors`` is {case: {variant: {"weave_f": %, "weave_re": %, "wobble_f": %,
    "wobble_re": %}}} (the JSON of ``motoflex study accuracy``); every variant of the JSON is
    drawn, in its order; returns the matplotlib Figure.
    """
    cases = list(errors)
    cols = min(len(cases), 2)
    rows = -(-len(cases) // cols)
    variants = list(errors[cases[0]])
    quantities = list(errors[cases[0]][variants[0]])
    panel_in = BAR_PITCH_IN * len(variants) * len(quantities) / 0.8 + 0.6
    fig, axes = plt.subplots(rows, cols, figsize=(10.5, panel_in * rows + 0.9), sharey=True,
                             sharex=True, squeeze=False, layout="constrained")
    peak = max(v for case in errors.values() for values in case.values()
               for v in values.values())
    width = 0.8 / len(variants)
    y = np.arange(len(quantities))[::-1]
    for ax, case in zip(axes.flat, cases):
        for i, variant in enumerate(variants):
            values = [max(errors[case][variant][q], 0.0) for q in quantities]
            bars = ax.barh(y - (i - (len(variants) - 1) / 2) * width, values, width,
                           label=VARIANT_LABELS.get(variant, variant))
            _label_bars(ax, bars)
        ax.set_yticks(y, [QUANTITY_LABELS.get(q, q) for q in quantities])
        ax.set_xscale("log")
        ax.set_xlim(FLOOR_PCT, max(CEILING_PCT, 30.0 * peak))
        ax.grid(axis="x", alpha=0.3, which="major")
        ax.set_title(case.replace("_", " ") + (" (all three flexible)" if case == "all" else
                                               " flexible"))
    for ax in axes.flat[len(cases):]:
        ax.set_visible(False)
    for ax in axes[-1, :]:
        ax.set_xlabel(r"$e_{RMS}$ [%] (log scale)")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside upper center", ncols=min(len(labels), 4),
               fontsize=9)
    return fig


def plot_accuracy_bars(errors, path):
    """Write :func:`accuracy_bars_figure` as PNG to ``path``; returns the path."""
    return save_png(accuracy_bars_figure(errors), path)


def plot_stability_curves(speeds, real_parts, path, labels=None, mode="weave"):
    """Fig. 4 style: real part of a tracked mode over speed [km/h], the boundary Re = 0 and
    the two speed ranges. ``speeds`` [m/s] (s,), ``real_parts`` [1/s] (curves, s)."""
    fig, ax = plt.subplots(figsize=(7, 4))
    kmh = ms_to_kmh(speeds)
    curves = np.atleast_2d(real_parts)
    for i, curve in enumerate(curves):
        ax.plot(kmh, curve, label=None if labels is None else labels[i])
    ax.axhline(0.0, color="black", linewidth=1.0)
    for boundary in (40.0, 100.0, 210.0):
        ax.axvline(boundary, color="grey", linestyle=":", linewidth=0.8)
    ax.set_xlabel("speed [km/h]")
    ax.set_ylabel(f"Re($\\lambda$) of {mode} [1/s]")
    if labels is not None:
        ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return save_png(fig, path)
