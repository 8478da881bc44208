"""Weave, wobble and capsize: named by frequency band and mode shape, tracked over speed by
eigenvector similarity (modal assurance criterion), never by sorting.

Mode shape: the rate part of the eigenvector (lateral velocity divided by the wheelbase, yaw,
roll, steer, rider lean and any other joint rates), as shares |phi_k|^2 / sum |phi|^2.
At the vehicle's reference speed (``reference_speed`` in its YAML, default 100 km/h; added to
the tracking grid when outside the requested speeds, so that a mode has the same name whatever
speeds are asked for):
- wobble: oscillatory, 5-12 Hz, the largest steer share (at least one half);
- weave: oscillatory, 0.5-5 Hz, the largest roll + yaw + lateral share;
- capsize: real, the slowest mode with roll + yaw + lateral share of at least one half.
Each is then followed speed by speed on a fine grid (steps of at most 0.3 m/s) to the
candidate with the largest MAC = |phi_a^H phi_b|^2 / (|phi_a|^2 |phi_b|^2) with the previous
shape; a mode whose best MAC falls below 0.5, or that changes kind (oscillatory/real), is lost
(None) from there on.
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from motoflex_ros.vehicle.linearize import is_singular
from motoflex_ros.vehicle.mode_names import MODE_NAMES

__all__ = ["ModalSweep", "modal_sweep", "mac", "eigen_decomposition", "WEAVE_BAND_HZ",
           "WOBBLE_BAND_HZ"]

WEAVE_BAND_HZ = (0.5, 5.0)
WOBBLE_BAND_HZ = (5.0, 12.0)
_MAX_STEP = 0.3
_MAC_LOST = 0.5


@dataclass(frozen=True)
class ModalSweep:
    """Eigenvalues over speed and the tracked modes.

    speeds [m/s] (s,), eigenvalues: tuple of 1-D complex arrays [1/s], one per speed (all
    finite eigenvalues); modes: name -> complex array (s,) with nan where the mode is not found
    (oscillatory modes reported with positive imaginary part); mode_shapes: name -> complex
    array (s, n) of right eigenvectors over ``state_names``, scaled so that their largest
    entry is 1 (nan where the mode is not found), e.g. to animate weave and wobble.
    """

    speeds: np.ndarray
    eigenvalues: tuple
    modes: dict
    mode_shapes: dict = None
    state_names: tuple = ()

    def frequency_hz(self, name):
        """Damped frequency Im(lambda)/(2 pi) [Hz] of a tracked mode over speed."""
        return self.modes[name].imag / (2.0 * np.pi)

    def real_part(self, name):
        """Real part [1/s] of a tracked mode over speed."""
        return self.modes[name].real


def mac(a, b):
    """Modal assurance criterion of two complex shape vectors (0..1)."""
    return np.abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)


def eigen_decomposition(lin, speeds):
    """Eigenvalues (s, n) and right eigenvectors (s, n, n) over speed; infinite eigenvalues of
    a singular E(v) are replaced by nan."""
    E, A = lin.pencil(speeds)
    if not is_singular(E):
        return np.linalg.eig(np.linalg.solve(E, A))
    values, vectors = [], []
    for e, a in zip(E, A):
        alpha, beta, vec = _generalized(a, e)
        finite = np.abs(beta) > 1e-12 * np.abs(alpha)
        values.append(np.divide(alpha, beta, out=np.full(alpha.shape, np.nan + 0j),
                                where=finite))
        vectors.append(vec)
    return np.array(values), np.array(vectors)


def _generalized(a, e):
    (alpha, beta), vec = scipy.linalg.eig(a, e, homogeneous_eigvals=True)
    return alpha, beta, vec


def _shape_groups(lin):
    """Index lists of the rate states by role, and the weights making them comparable."""
    names = lin.state_names
    roles = lin.system.model.roles
    rate = {n[:-5]: i for i, n in enumerate(names) if n.endswith("_rate")}
    wheels = lin.system.model.wheels
    wheelbase = abs(wheels[0].centre[0] - wheels[1].centre[0])
    weights = np.ones(len(rate))
    order = list(rate.values())
    if "y" in rate:
        weights[order.index(rate["y"])] = 1.0 / wheelbase
    groups = {"lateral": [rate[k] for k in ("y", "yaw", "roll") if k in rate],
              "steer": [rate[roles["steer"]]] if roles.get("steer") in rate else []}
    return order, weights, groups


def _shares(vectors, order, weights, groups):
    phi = vectors[..., order, :] * weights[:, None]
    power = np.abs(phi) ** 2
    power = power / power.sum(axis=-2, keepdims=True)
    pos = {i: k for k, i in enumerate(order)}
    return {g: power[..., [pos[i] for i in idx], :].sum(axis=-2) for g, idx in groups.items()}


def _is_real(value):
    return np.abs(value.imag) <= 1e-9 * np.maximum(np.abs(value), 1.0)


def _pick_reference(values, shares):
    freq = values.imag / (2.0 * np.pi)
    osc = values.imag > 0
    picks = {}
    wobble = osc & (freq >= WOBBLE_BAND_HZ[0]) & (freq <= WOBBLE_BAND_HZ[1]) & (
        shares["steer"] >= 0.5)
    if wobble.any():
        picks["wobble"] = int(np.argmax(np.where(wobble, shares["steer"], -1.0)))
    weave = osc & (freq >= WEAVE_BAND_HZ[0]) & (freq <= WEAVE_BAND_HZ[1])
    if weave.any():
        picks["weave"] = int(np.argmax(np.where(weave, shares["lateral"], -1.0)))
    capsize = _is_real(values) & (shares["lateral"] >= 0.5) & np.isfinite(values)
    if capsize.any():
        picks["capsize"] = int(np.argmin(np.where(capsize, np.abs(values), np.inf)))
    return picks


def _follow(values, shapes, start, index, step):
    """Track one mode from grid point ``start`` in direction ``step``; returns {grid: index}."""
    track = {start: index}
    oscillatory = values[start, index].imag > 0
    shape = shapes[start, :, index]
    norms = np.sum(np.abs(shapes) ** 2, axis=1)
    k = start + step
    while 0 <= k < len(values):
        ok = (values[k].imag > 0) if oscillatory else _is_real(values[k])
        ok &= np.isfinite(values[k])
        if not ok.any():
            break
        macs = np.abs(shape.conj() @ shapes[k]) ** 2 / (np.vdot(shape, shape).real * norms[k])
        macs = np.where(ok, macs, -1.0)
        best = int(np.argmax(macs))
        if macs[best] < _MAC_LOST:
            break
        track[k] = best
        shape = shapes[k, :, best]
        k += step
    return track


def _grid(speeds, reference):
    """The requested speeds and the reference speed, with points inserted in any gap wider
    than the tracking step."""
    points = np.unique(np.append(speeds, reference))
    pieces = [points[:1]]
    for low, high in zip(points[:-1], points[1:]):
        count = int(np.ceil((high - low) / _MAX_STEP))
        pieces.append(np.linspace(low, high, count + 1)[1:])
    return np.concatenate(pieces)


def modal_sweep(lin, speeds):
    """ModalSweep of a LinearVehicle at the given speeds [m/s] (module docstring)."""
    speeds = np.asarray(speeds, float)
    reference = lin.system.model.reference_speed
    grid = _grid(speeds, reference)
    values, vectors = eigen_decomposition(lin, grid)
    order, weights, groups = _shape_groups(lin)
    shapes = vectors[:, order, :] * weights[None, :, None]
    ref = int(np.argmin(np.abs(grid - reference)))
    ref_shares = {g: s[ref] for g, s in _shares(vectors, order, weights, groups).items()}
    picks = _pick_reference(values[ref], ref_shares)
    at = np.searchsorted(grid, speeds)
    modes, mode_shapes = {}, {}
    for name in MODE_NAMES:
        tracked = np.full(len(grid), np.nan + 1j * np.nan)
        vecs = np.full((len(grid), values.shape[1]), np.nan + 1j * np.nan)
        if name in picks:
            for step in (-1, 1):
                for k, j in _follow(values, shapes, ref, picks[name], step).items():
                    tracked[k] = values[k, j]
                    vecs[k] = _scaled(vectors[k, :, j])
        modes[name], mode_shapes[name] = tracked[at], vecs[at]
    finite = [v[np.isfinite(v)] for v in values[at]]
    return ModalSweep(speeds, tuple(finite), modes, mode_shapes, tuple(lin.state_names))


def _scaled(vector):
    """Eigenvector divided by its largest-magnitude entry (that entry becomes 1)."""
    return vector / vector[np.argmax(np.abs(vector))]
