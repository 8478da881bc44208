"""Plots of the studies (Passigato et al. 2023): Fig. 10 Pearson bars, Fig. 8 e_RMS bars and
Fig. 4-style stability-index curves. PNG files, written atomically."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.plots.labels import QUANTITY_LABELS, VARIANT_LABELS  # noqa: E402
from motoflex_ros.plots.vehicle import save_png  # noqa: E402
from motoflex_ros.units import ms_to_kmh  # noqa: E402

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


def pearson_bars_figure(pearson, modes=("weave", "wobble"), ranges=("low", "high")):
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


def plot_pearson_bars(pearson, path, modes=("weave", "wobble"), ranges=("low", "high")):
    """Write :func:`pearson_bars_figure` as PNG to ``path``; returns the path."""
    return save_png(pearson_bars_figure(pearson, modes, ranges), path)


def _label_bars(ax, bars):
    for bar in bars:
        value = bar.get_height()
        ax.annotate(f"{value:.2g}", (bar.get_x() + bar.get_width() / 2, max(value, FLOOR_PCT)),
                    xytext=(0, 2), textcoords="offset points", ha="center", va="bottom",
                    rotation=90, fontsize=6)


def accuracy_bars_figure(errors):
    """Fig. 8: e_RMS% (eq. 18) of each lumped variant, per case (frame, ..., all), on a log
    axis (errors from 0.01 % to 100 % side by side) with each bar's value written on it.

    ``errors`` is {case: {variant: {"weave_f": %, "weave_re": %, "wobble_f": %,
    "wobble_re": %}}} (the JSON of ``motoflex study accuracy``); returns the matplotlib Figure.
    """
    cases = list(errors)
    cols = min(len(cases), 2)
    rows = -(-len(cases) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(10, 3.6 * rows), sharey=True, squeeze=False,
                             layout="constrained")
    for ax, case in zip(axes.flat, cases):
        variants = errors[case]
        quantities = list(next(iter(variants.values())))
        series = {VARIANT_LABELS.get(v, v): [max(values[q], 0.0) for q in quantities]
                  for v, values in variants.items()}
        for bars in _grouped_bars(ax, [QUANTITY_LABELS.get(q, q) for q in quantities], series,
                                  zero_line=False):
            _label_bars(ax, bars)
        ax.tick_params(axis="x", labelsize=8)
        ax.set_yscale("log")
        ax.set_ylim(FLOOR_PCT, CEILING_PCT)
        ax.grid(axis="y", alpha=0.3, which="both")
        ax.set_title(case.replace("_", " "))
    for ax in axes.flat[len(cases):]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$e_{RMS}$ [%] (log scale)")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=min(len(labels), 4),
               fontsize=8)
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
