"""Fig. 9 of Passigato et al. 2023: weave and wobble of the front-assembly case against speed,
flexible (ground truth) beside the lumped models. PNG, written atomically."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.plots.vehicle import save_png  # noqa: E402
from motoflex_ros.units import ms_to_kmh  # noqa: E402
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["plot_mode_curves"]

_STYLE = {"flexible": dict(color="black", linewidth=2.0),
          "state_of_the_art": dict(color="tab:red", linestyle="--"),
          "static": dict(color="tab:blue"), "torsion": dict(color="tab:green", linestyle=":"),
          "bending": dict(color="tab:orange", linestyle="-.")}


def plot_mode_curves(speeds, curves, path, models=("flexible", "state_of_the_art", "static"),
                     title="front assembly"):
    """Frequency [Hz] and real part [1/s] of weave and wobble over speed [m/s] (Fig. 9).

    ``curves``: {model: {"weave": eigenvalues (speeds,), "wobble": ...}} [1/s].
    """
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    kmh = ms_to_kmh(speeds)
    for col, mode in enumerate(STUDIED_MODES):
        for model in models:
            values = np.asarray(curves[model][mode])
            style = _STYLE.get(model, {})
            axes[0, col].plot(kmh, values.imag / (2 * np.pi), label=model, **style)
            axes[1, col].plot(kmh, values.real, label=model, **style)
        axes[0, col].set_title(f"{mode} ({title})")
        axes[0, col].set_ylabel("frequency [Hz]")
        axes[1, col].set_ylabel("real part [1/s]")
        axes[1, col].set_xlabel("speed [km/h]")
        for ax in axes[:, col]:
            ax.grid(alpha=0.3)
    axes[0, 0].legend()
    fig.tight_layout()
    return save_png(fig, path)
