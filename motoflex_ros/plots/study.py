"""Plots of the studies (Passigato et al. 2023): Fig. 10 Pearson bars, Fig. 8 e_RMS bars and
Fig. 4-style stability-index curves. PNG files, written atomically."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.plots.vehicle import save_png  # noqa: E402
from motoflex_ros.units import ms_to_kmh  # noqa: E402

__all__ = ["plot_pearson_bars", "plot_accuracy_bars", "plot_stability_curves"]

_RANGE_LABELS = {"low": "40-100 km/h", "high": "100-210 km/h"}
_FACTOR_LABELS = {"k_tf": "$k_{tf}$", "k_bf": "$k_{bf}$", "k_ta": "$k_{ta}$",
                  "k_ba": "$k_{ba}$", "k_ts": "$k_{ts}$", "k_bs": "$k_{bs}$"}


def _grouped_bars(ax, groups, series):
    """Bars of several series side by side over the groups; series: {label: values}."""
    width = 0.8 / max(len(series), 1)
    x = np.arange(len(groups))
    for i, (label, values) in enumerate(series.items()):
        ax.bar(x + (i - (len(series) - 1) / 2) * width, values, width, label=label)
    ax.set_xticks(x, groups)
    ax.axhline(0.0, color="black", linewidth=0.8)
    ax.grid(axis="y", alpha=0.3)


def plot_pearson_bars(pearson, path, modes=("weave", "wobble"), ranges=("low", "high")):
    """Fig. 10: Pearson coefficient of every stiffness with the weave and wobble indices.

    ``pearson`` is {"<mode>_<range>": {factor: rho}} as from
    :func:`motoflex_ros.study.correlation.pearson_table`; writes a PNG to ``path``.
    """
    fig, axes = plt.subplots(1, len(modes), figsize=(6 * len(modes), 4), sharey=True)
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
    fig.tight_layout()
    return save_png(fig, path)


def plot_accuracy_bars(errors, path):
    """Fig. 8: e_RMS% (eq. 18) of each lumped variant, per case (frame, ..., all).

    ``errors`` is {case: {variant: {"weave_f": %, "weave_re": %, "wobble_f": %,
    "wobble_re": %}}} (the JSON of ``motoflex study accuracy``); writes a PNG to ``path``.
    """
    cases = list(errors)
    fig, axes = plt.subplots(1, len(cases), figsize=(4.5 * len(cases), 4), sharey=True)
    for ax, case in zip(np.atleast_1d(axes), cases):
        variants = errors[case]
        quantities = list(next(iter(variants.values())))
        _grouped_bars(ax, quantities, {variant: [values[q] for q in quantities]
                                       for variant, values in variants.items()})
        ax.set_title(case.replace("_", " "))
    np.atleast_1d(axes)[0].set_ylabel(r"$e_{RMS}$ [%]")
    np.atleast_1d(axes)[-1].legend()
    fig.tight_layout()
    return save_png(fig, path)


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
