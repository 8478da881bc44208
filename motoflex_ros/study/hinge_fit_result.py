"""The result of a hinge fit (:mod:`motoflex_ros.study.fitted`) and the identification
results with its "fitted" hinges in them."""
from dataclasses import dataclass, field

import numpy as np

from motoflex_ros.identify.results import ResultsFile

__all__ = ["HingeFit", "with_fitted"]


@dataclass(frozen=True, eq=False)
class HingeFit:
    """Result of a hinge fit.

    names: the components; hinges, static: {component: Hinge}; errors, static_errors: {quantity:
    e_RMS%} of the fitted and the static hinges (same evaluation); objective: J [%^2];
    conditioning: {component: {label: {quantity: e_RMS%}}}; evaluations: objective calls;
    seconds: wall time; how: "single", or "jointly" for several components; start: the label
    of the start the result came from; starts: {label: {"objective": J on the search speeds,
    "hinges": where the search from it ended}}; spring_errors: {quantity: e_RMS%} of the
    motorcycle with the components' whole FE end stiffness in the hinges' place (None where
    its weave or wobble could not be followed).
    """

    names: tuple
    hinges: dict
    static: dict
    errors: dict
    static_errors: dict
    objective: float
    conditioning: dict
    evaluations: int
    seconds: float
    how: str
    speeds: np.ndarray = field(default=None, repr=False)
    start: str = "static"
    starts: dict = field(default_factory=dict)
    spring_errors: dict = None

    def identified(self, identified):
        """A copy of the identification results with a "fitted" model in each fitted
        component (the keys of a static one), for :func:`build_variant` 'fitted'."""
        return with_fitted(identified, [self])

    def to_dict(self):
        """Plain dict (JSON): per component the fitted and static hinges and the conditioning."""
        return {"how": self.how, "objective": self.objective, "evaluations": self.evaluations,
                "seconds": self.seconds, "start": self.start, "starts": self.starts,
                "errors": dict(self.errors),
                "static_errors": dict(self.static_errors),
                "end_stiffness_errors": (dict(self.spring_errors) if self.spring_errors
                                         else None),
                "components": {name: {"fitted": self.hinges[name].to_dict(),
                                      "static": self.static[name].to_dict(),
                                      "conditioning": self.conditioning[name]}
                               for name in self.names}}


def with_fitted(identified, fits):
    """A copy of the identification results with the "fitted" hinges of all ``fits``."""
    out = {name: dict(result) for name, result in identified.items()}
    if isinstance(identified, ResultsFile):
        out = ResultsFile(out, identified.source)
    for fit in fits:
        for name, hinge in fit.hinges.items():
            out[name]["fitted"] = hinge.to_dict()
    return out
