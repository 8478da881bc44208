"""The bench file of a real rig (YAML): what the measured identification needs besides the data,
read into a :class:`~motoflex_ros.identify.physical_bench.PhysicalBench`.

A physical bench has no finite-element model: the identification of measurements
(:mod:`motoflex_ros.identify.measured`) takes the geometry from this file, with exactly these
keys::

    bench: my_swingarm
    loaded_end: [0.60, 0.0, 0.0]      # q0 [m], clamp frame, unloaded
    markers: from_data                 # or [[dx, dy, dz], ...] offsets from q0 [m]
    sensor: {noise_m: 5.0e-6, latency_s: 0.0}
    carried:                           # optional: for the principal hinges
      mass_kg: 20.1
      com_m: [0.62, 0.0, -0.05]        # clamp frame [m]
      inertia_kg_m2: {xx: 0.9, yy: 1.4, zz: 0.5}   # about the centre of mass (xy, xz, yz: 0)
      passes_moment: true              # false: a spherical joint at q0 (only the mass counts)

``bench`` names the component (results are filed under it; the default topic names of a bag
or a live rig are ``/bench/<bench>/load`` and ``/bench/<bench>/markers/measured``). The
clamp frame is the paper's component frame (Passigato et al. 2023, Fig. 2): clamp at the
origin O, the component's plane x-z, the lateral load along y. ``markers``: the marker offsets
from q0 with the component unloaded, in the order of the data's markers, or ``from_data``:
their mean positions over the samples before the first load (a quiet lead-in of at least
:data:`~motoflex_ros.identify.physical_bench.MIN_REFERENCE_FRAMES` frames).
``sensor.noise_m`` [m]: the marker noise (standard deviation per coordinate; used to tell a
motion from noise, never for the intervals, which come from the scatter of the data);
``sensor.latency_s`` [s]: how much later than the capture a marker frame is stamped (CSV ``t``,
message header stamps). ``carried``: what hangs from the loaded end in the vehicle (the front
assembly's wheel carrier and wheel, the swingarm's wheel): the metric of the principal hinges
(:mod:`motoflex_ros.identify.principal`); without it they are reported as not identified.
"""
import re

import numpy as np

from motoflex_ros.bench.sensor import MAX_NOISE_M
from motoflex_ros.config import Field, load_yaml, number, positive, shown, validate
from motoflex_ros.errors import ConfigError
from motoflex_ros.identify.measurements import MIN_MARKERS
from motoflex_ros.identify.physical_bench import (
    MIN_ARM_M,
    PhysicalBench,
    check_marker_spread,
)
from motoflex_ros.identify.principal import CarriedInertia
from motoflex_ros.inertia import check_inertia, inertia_matrix

__all__ = ["load_bench", "bench_from_dict", "FROM_DATA", "BENCH_SCHEMA"]

FROM_DATA = "from_data"
MAX_SIZE_M = 10.0
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")

BENCH_SCHEMA = Field("mapping", fields={
    "bench": Field("str", help="the component's name: a letter, then letters, digits or _"),
    "loaded_end": Field("vec3", -MAX_SIZE_M, MAX_SIZE_M,
                        help="q0 [m], clamp frame, unloaded: [x, y, z]"),
    "markers": Field("any", help=f"'{FROM_DATA}' or a list of >= {MIN_MARKERS} offsets "
                                 f"[dx, dy, dz] from q0 [m]"),
    "sensor": Field("mapping", help="{noise_m, latency_s}", fields={
        "noise_m": number(0.0, MAX_NOISE_M, help=f"marker noise std [m] in [0, "
                                                 f"{MAX_NOISE_M:g}]"),
        "latency_s": number(0.0, 1.0, help="stamp minus capture time [s] in [0, 1]"),
    }),
    "carried": Field("mapping", required=False, default=None, fields={
        "mass_kg": positive(1e5, help="carried mass [kg] > 0"),
        "com_m": Field("vec3", -MAX_SIZE_M, MAX_SIZE_M, help="its centre of mass [m], clamp "
                                                             "frame"),
        "inertia_kg_m2": Field("mapping", help="{xx, yy, zz[, xy, xz, yz]} about the centre "
                                               "of mass [kg m^2]", fields={
            name: number(-1e5, 1e5, required=name in ("xx", "yy", "zz"), default=0.0)
            for name in ("xx", "yy", "zz", "xy", "xz", "yz")}),
        "passes_moment": Field("bool", required=False, default=True),
    }),
})


def _markers(value, source):
    if value == FROM_DATA:
        return None
    if not isinstance(value, list):
        raise ConfigError(source, "markers", f"expected '{FROM_DATA}' or a list of >= "
                                             f"{MIN_MARKERS} offsets [dx, dy, dz] [m], got "
                                             f"{shown(value)}")
    if len(value) < MIN_MARKERS:
        raise ConfigError(source, "markers", f"expected at least {MIN_MARKERS} markers (a "
                                             f"rigid fit needs three that span a plane), got "
                                             f"{len(value)}")
    vec = Field("vec3", -MAX_SIZE_M, MAX_SIZE_M)
    offsets = np.array([validate(v, vec, source, f"markers[{i}]") for i, v in enumerate(value)])
    check_marker_spread(offsets, source, "markers")
    return offsets


def bench_from_dict(data, source="bench file"):
    """PhysicalBench of a mapping with the bench file's keys (validated; ConfigError naming
    the source and the key)."""
    data = validate(data, BENCH_SCHEMA, source)
    if not _NAME.match(data["bench"]):
        raise ConfigError(source, "bench", f"'{data['bench']}' is not a name: a letter, then "
                                           f"letters, digits or _ (it names the results and the "
                                           f"topics /bench/<bench>/...)")
    q0 = np.array(data["loaded_end"], float)
    arm = float(np.hypot(q0[0], q0[2]))
    if arm < MIN_ARM_M:
        raise ConfigError(source, "loaded_end", f"q0 {q0.tolist()} is {arm:.3g} m from the "
                                                f"clamp in the x-z plane, allowed >= "
                                                f"{MIN_ARM_M:g} m (the line O-q0 of eqs. 3-7)")
    return PhysicalBench(data["bench"], q0, _markers(data["markers"], source),
                     data["sensor"]["noise_m"], data["sensor"]["latency_s"], str(source),
                     _carried(data["carried"], source))


def _carried(data, source):
    """CarriedInertia of the bench file's ``carried`` key (None without it)."""
    if data is None:
        return None
    tensor = inertia_matrix(data["inertia_kg_m2"])
    check_inertia(tensor, source, "carried.inertia_kg_m2")
    return CarriedInertia(data["mass_kg"], np.array(data["com_m"], float), tensor,
                          data["passes_moment"], f"{source}: carried")


def load_bench(path):
    """Load and validate a bench file (YAML) into a
    :class:`~motoflex_ros.identify.physical_bench.PhysicalBench`."""
    return bench_from_dict(load_yaml(path), str(path))

