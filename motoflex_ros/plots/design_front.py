"""Plots of ``motoflex study design``: the mass / stability-margin front and the stiffness
changes of the lightest feasible design beside the paper's advice (Sect. 5.3, Fig. 10)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.plots.vehicle import save_png  # noqa: E402

__all__ = ["design_front_figure", "plot_design_front", "plot_stiffness_changes"]


def design_front_figure(design):
    """Figure: structural mass [kg] against the smallest stability margin min_i (s_i -
    floor_i) of the Pareto points, with the nominal and the lightest feasible design;
    ``design`` is the JSON of ``motoflex study design --json`` (or its dict)."""
    floors = design["floors"]

    def margin(point):
        return min(point["indices"][n] - f for n, f in floors.items())

    fig, ax = plt.subplots(figsize=(7, 5))
    pts = np.array([[margin(p), p["mass_kg"]] for p in design["pareto"]]).reshape(-1, 2)
    ax.plot(pts[:, 0], pts[:, 1], "o", label="Pareto front (NSGA-II)")
    nominal = design["nominal"]
    ax.plot([margin(nominal)], [nominal["mass_kg"]], "ks", label="nominal")
    lightest = design.get("lightest_feasible")
    if lightest:
        ax.plot([margin(lightest)], [lightest["mass_kg"]], "r*", markersize=12,
                label="lightest feasible")
    ax.axvline(0.0, color="grey", linewidth=0.8)
    ax.set_xlabel("smallest stability margin min(s_i - floor_i) (eq. 15)")
    ax.set_ylabel("structural mass of the members [kg]")
    ax.grid(alpha=0.3)
    ax.legend()
    return fig


def plot_design_front(result, path):
    """Write :func:`design_front_figure` of a DesignStudyResult as PNG; returns the path."""
    return save_png(design_front_figure(result.to_dict()), path)


def plot_stiffness_changes(result, path):
    """Bars: relative change [%] of each component's static stiffness k (eq. 8) and of the
    first torsion and bending modal stiffness (Fig. 10's factors) in the lightest feasible
    design, each factor labelled with the paper's advice (Sect. 5.3)."""
    from motoflex_ros.study.design_study import PAPER_ADVICE

    fig, (ax_k, ax_m) = plt.subplots(1, 2, figsize=(12, 5),
                                     gridspec_kw={"width_ratios": [1, 2]})
    k_static = result.stiffness["k_static"]
    values = [100.0 * v for v in k_static.values()]
    ax_k.bar(np.arange(len(values)), values, color=["C0" if v >= 0 else "C3" for v in values])
    ax_k.set_xticks(np.arange(len(values)), list(k_static), rotation=15)
    ax_k.set_ylabel("change of the lightest feasible design [%]")
    ax_k.set_title("k about the static axis (eq. 8)")
    modal = {f: v for f, v in result.stiffness["modal"].items() if v is not None}
    values = [100.0 * v for v in modal.values()]
    ax_m.bar(np.arange(len(values)), values, color=["C0" if v >= 0 else "C3" for v in values])
    ax_m.set_xticks(np.arange(len(values)), list(modal))
    for i, f in enumerate(modal):
        ax_m.annotate("paper: " + PAPER_ADVICE[f].split(" (")[0], (i, values[i]), ha="center",
                      va="bottom" if values[i] >= 0 else "top", fontsize=8)
    ax_m.set_title("first torsion / bending modal stiffness (Fig. 10 factors)")
    for ax in (ax_k, ax_m):
        ax.axhline(0.0, color="black", linewidth=0.8)
        ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return save_png(fig, path)
