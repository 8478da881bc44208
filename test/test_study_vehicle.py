"""Mode continuation on the vehicle engine's touring motorcycle against its modal sweep.

The vehicle engine names weave and wobble by mode shape and follows them by MAC on full
generalized eigendecompositions (QZ); the study's continuation must give the same curves.
"""
import numpy as np
import pytest

from motoflex_ros.config import resolve_config
from motoflex_ros.study.continuation import continue_eigenpairs, nearest_eigenpairs
from motoflex_ros.study.stability_index import stability_index
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

SPEEDS = np.linspace(40.0, 210.0, 171) / 3.6


@pytest.fixture(scope="module")
def touring():
    lin = linearize(load_vehicle(resolve_config("vehicles", "touring")))
    return lin, modal_sweep(lin, SPEEDS)


def test_touring_weave_wobble_equal_modal_sweep(touring):
    lin, sweep = touring
    e, a = lin.pencil(SPEEDS)
    targets = [sweep.modes["weave"][0], sweep.modes["wobble"][0]]
    lam0, vec0 = nearest_eigenpairs(a[None, 0], targets, descriptor=e[None, 0])
    result = continue_eigenpairs((e[None], a[None]), lam0, vec0, speeds=SPEEDS)
    assert np.all(result.converged) and result.step_mac.min() > 0.99
    for i, mode in enumerate(("weave", "wobble")):
        reference = sweep.modes[mode]
        assert np.all(np.isfinite(reference))
        np.testing.assert_allclose(result.eigenvalues[0, :, i], reference, rtol=1e-9)
    # the stability index of the tracked curves equals that of the engine's curves
    for name in ("low", "high"):
        ours = stability_index(SPEEDS, result.eigenvalues[0, :, 1].real[None], name)
        theirs = stability_index(SPEEDS, sweep.real_part("wobble")[None], name)
        np.testing.assert_allclose(ours.s, theirs.s, rtol=1e-9)
