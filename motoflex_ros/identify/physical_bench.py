"""A physical bench as the identification of measurements takes it: what it needs besides the
data, and the checks the data must pass.

A physical bench has no finite-element model: :mod:`motoflex_ros.identify.measured` takes its
geometry from a :class:`PhysicalBench` (read from the rig's bench file at the edge,
:mod:`motoflex_ros.formats.bench_file`, where the keys are described). The clamp frame is the
paper's component frame (Passigato et al. 2023, Fig. 2): clamp at the origin O, the component's
plane x-z, the lateral load along y. ``q0`` [m]: the loaded end, unloaded; ``offsets``: the
marker offsets from q0 [m] with the component unloaded, or None: their mean positions over the
samples before the first load (a quiet lead-in of at least :data:`MIN_REFERENCE_FRAMES`
frames); ``noise_m`` [m]: the marker noise (standard deviation per coordinate; used to tell a
motion from noise, never for the intervals, which come from the scatter of the data);
``latency_s`` [s]: how much later than the capture a marker frame is stamped; ``carried``: the
:class:`~motoflex_ros.identify.principal.CarriedInertia` of what hangs from the loaded end (the
principal hinges' metric; None: they are reported as not identified).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ConfigError

__all__ = ["PhysicalBench", "check_marker_spread", "MIN_REFERENCE_FRAMES", "MIN_ARM_M",
           "MIN_MARKER_SPREAD_M"]

MIN_REFERENCE_FRAMES = 10
"""Frames before the first load that ``markers: from_data`` needs for the reference (their
mean; its scatter enters the static intervals)."""
MIN_ARM_M = 1e-3
"""Smallest distance [m] of q0 from the clamp in the x-z plane: the line O-q0 of eqs. (3)-(7)
must be defined."""
MIN_MARKER_SPREAD_M = 1e-3
"""Smallest spread [m] of the markers across their best-fit line (second singular value of the
centred positions), as a protocol's markers (:data:`motoflex_ros.bench.protocols.
MIN_MARKER_SPREAD_M`): collinear markers leave the rotation about their line unobserved."""


@dataclass(frozen=True)
class PhysicalBench:
    """A physical bench: name, q0 [m], marker offsets (n, 3) [m] or None (from the data),
    noise_m [m], latency_s [s], the file it came from and the CarriedInertia (or None)."""

    name: str
    q0: np.ndarray
    offsets: object
    noise_m: float
    latency_s: float
    source: str = "bench file"
    carried: object = None

    @property
    def n_markers(self):
        """Number of markers the file gives (None: taken from the data)."""
        return None if self.offsets is None else len(self.offsets)


def check_marker_spread(points, source, key, what="the markers"):
    """ConfigError unless the centred ``points`` (n, 3) [m] span a plane (second singular value
    at least MIN_MARKER_SPREAD_M); returns the spread [m]."""
    points = np.asarray(points, float)
    spread = float(np.linalg.svd(points - points.mean(axis=0), compute_uv=False)[1])
    if not spread >= MIN_MARKER_SPREAD_M:
        raise ConfigError(source, key, f"{what} are collinear or coincident (second singular "
                                       f"value of the centred positions {spread:.3g} m, allowed "
                                       f">= {MIN_MARKER_SPREAD_M:g} m); the rotation about "
                                       f"their line cannot be measured: place at least three "
                                       f"markers that span a plane")
    return spread
