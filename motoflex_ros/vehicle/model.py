"""Vehicle description: bodies, joints, wheels, built from a YAML file or a dict.

A body is rigid (mass [kg], centre of mass [m] and inertia tensor about it [kg m^2], all in the
reference configuration, REP-103 axes). A body may be given as named ``parts`` that are combined
with the parallel-axis theorem. A massless body (mass 0, as the lumped-stiffness variants use
between wheel carrier and wheel) is allowed: the engine works in descriptor form. Joints are
fixed, revolute (any axis through any point) or prismatic, with optional rotational spring and
damper. Wheels roll on a toroidal tyre (rolling radius r, crown radius r_c).
"""
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from motoflex_ros.config import load_yaml, validate
from motoflex_ros.errors import ConfigError
from motoflex_ros.vehicle.schema import REFERENCE_SPEED, VEHICLE_SCHEMA
from motoflex_ros.vehicle.tyre import tyre_from_config

__all__ = ["Body", "Joint", "Wheel", "VehicleModel", "load_vehicle", "vehicle_from_dict",
           "inertia_matrix", "check_inertia", "parallel_axis", "composite_inertia",
           "combine_parts", "WHEEL_AXIS_TOLERANCE_RAD"]

WHEEL_AXIS_TOLERANCE_RAD = 1e-3
"""Largest angle [rad] between a wheel's spin axis and the lateral axis y. The engine linearizes
about upright, straight running: a wheel whose axis is toed (x) or cambered (z) would not roll
straight ahead upright in the reference configuration (an x axis makes the contact frame
singular)."""


@dataclass(frozen=True)
class Body:
    """Rigid body: mass [kg], com [m] and inertia [kg m^2] about the com (reference config)."""

    name: str
    mass: float
    com: np.ndarray
    inertia: np.ndarray


@dataclass(frozen=True)
class Joint:
    """Joint between parent and child body; axis is a unit vector, point [m] on the axis.

    kind 'revolute' or 'prismatic' adds one coordinate, 'fixed' none. stiffness [N m/rad]
    (or [N/m]) and damping [N m s/rad] act on the joint coordinate.
    """

    name: str
    kind: str
    parent: str
    child: str
    axis: np.ndarray
    point: np.ndarray
    stiffness: float = 0.0
    damping: float = 0.0


@dataclass(frozen=True)
class Wheel:
    """Wheel spinning about ``axis`` through ``centre`` on its carrier body.

    radius r [m] (rolling radius in the reference configuration), crown_radius r_c [m] of the
    tyre cross-section, mass [kg], diametral and spin inertia [kg m^2], tyre a LinearTyre or
    None for a knife-edge wheel rolling without slip.
    """

    name: str
    carrier: str
    centre: np.ndarray
    axis: np.ndarray
    radius: float
    crown_radius: float
    mass: float
    diametral_inertia: float
    spin_inertia: float
    tyre: object = None

    @property
    def inertia(self):
        """Inertia tensor about the centre [kg m^2]: diametral_inertia about every axis normal
        to the spin axis a, spin_inertia about a: I_d (1 - a a^T) + I_s a a^T."""
        a = self.axis
        inertia = self.diametral_inertia * (np.eye(3) - np.outer(a, a))
        return inertia + self.spin_inertia * np.outer(a, a)


@dataclass(frozen=True)
class VehicleModel:
    """A complete vehicle description (see module docstring); roles map 'steer' etc. to joints;
    reference_speed [m/s] is where weave, wobble and capsize are named before tracking.

    elements: extra force elements (e.g. superelement stiffness/damping acting on joint or
    modal coordinates), objects with ``generalized_residual(system, frames, q, u, udot)``
    returning a complex-safe vector over all coordinates that is added to the residual of the
    equations of motion (inertia minus applied forces: a spring k q enters as +k q). An element
    may also have ``bind(tree)``: the compiled system then holds what it returns instead (e.g.
    the element with its coordinate indices looked up once, not in every residual call)."""

    name: str
    source: str
    gravity: float
    root: str
    bodies: tuple
    joints: tuple
    wheels: tuple
    roles: dict = field(default_factory=dict)
    reference_speed: float = REFERENCE_SPEED
    flex: dict = field(default_factory=dict)
    elements: tuple = ()

    def body(self, name):
        """The body called ``name``."""
        return next(b for b in self.bodies if b.name == name)

    def total_mass(self):
        """Sum of body and wheel masses [kg]."""
        return sum(b.mass for b in self.bodies) + sum(w.mass for w in self.wheels)


def inertia_matrix(spec):
    """3x3 inertia tensor [kg m^2] from a mapping xx, yy, zz, xy, xz, yz (tensor entries)."""
    xy, xz, yz = spec.get("xy", 0.0), spec.get("xz", 0.0), spec.get("yz", 0.0)
    return np.array([[spec["xx"], xy, xz], [xy, spec["yy"], yz], [xz, yz, spec["zz"]]], float)


def check_inertia(tensor, source, key):
    """Raise ConfigError unless the tensor is positive definite with principal moments that
    satisfy the triangle inequality (I1 + I2 >= I3 for every ordering)."""
    moments = np.linalg.eigvalsh(tensor)
    if moments[0] <= 0.0:
        raise ConfigError(source, key, "inertia tensor is not positive definite (principal "
                                       f"moments {np.round(moments, 6).tolist()} kg m^2)")
    if moments[0] + moments[1] < moments[2] * (1.0 - 1e-9):
        raise ConfigError(source, key, "inertia tensor violates the triangle inequality "
                                       f"(principal moments {np.round(moments, 6).tolist()}: "
                                       "I1 + I2 must be >= I3)")


def parallel_axis(mass, offset):
    """Parallel-axis (Steiner) term m (|d|^2 1 - d d^T) [kg m^2].

    What a point mass ``mass`` [kg] at ``offset`` d [m] from a reference point adds to an
    inertia tensor about that point.
    """
    d = np.asarray(offset)
    return mass * ((d @ d) * np.eye(3) - np.outer(d, d))


def composite_inertia(items):
    """Mass [kg], centre of mass [m] and inertia tensor about it [kg m^2] of rigid items.

    Parameters
    ----------
    items : iterable of (mass, com, inertia)
        Each item's mass [kg], centre of mass [m] and inertia tensor about its own centre of
        mass [kg m^2], all in one frame.

    Returns
    -------
    mass, com, inertia
        Total mass, common centre of mass c = sum m_i c_i / m, and
        I = sum (I_i + :func:`parallel_axis` (m_i, c_i - c)).

    """
    items = list(items)
    mass = sum(m for m, _, _ in items)
    com = sum(m * np.asarray(c) for m, c, _ in items) / mass
    inertia = np.zeros((3, 3))
    for m, c, own in items:
        inertia += own + parallel_axis(m, np.asarray(c) - com)
    return mass, com, inertia


def combine_parts(parts, source, key):
    """Mass [kg], com [m] and inertia about the com [kg m^2] of named parts (parallel axis)."""
    items = []
    for name, part in parts.items():
        own = inertia_matrix(part["inertia"])
        check_inertia(own, source, f"{key}.parts.{name}.inertia")
        items.append((part["mass"], part["com"], own))
    return composite_inertia(items)

def _body(name, spec, source):
    key = f"bodies.{name}"
    if spec["parts"]:
        for sibling in ("mass", "com", "inertia"):
            if spec[sibling] is not None:
                raise ConfigError(source, f"{key}.{sibling}",
                                  "not allowed beside parts (the parts give the body's mass, "
                                  "com and inertia): give either parts or mass, com and inertia")
        mass, com, inertia = combine_parts(spec["parts"], source, key)
    else:
        massless = spec["mass"] == 0.0 and spec["inertia"] is None
        for needed in ("mass", "com") if massless else ("mass", "com", "inertia"):
            if spec[needed] is None:
                raise ConfigError(source, f"{key}.{needed}", "missing (give mass, com and "
                                                             "inertia, or parts; a massless "
                                                             "body: mass 0 and com)")
        mass, com = spec["mass"], np.asarray(spec["com"], float)
        inertia = np.zeros((3, 3)) if massless else inertia_matrix(spec["inertia"])
        if not massless:
            check_inertia(inertia, source, f"{key}.inertia")
    return Body(name, float(mass), np.asarray(com, float), inertia)


def _lateral_axis(vector, source, key):
    """A wheel's unit spin axis, within WHEEL_AXIS_TOLERANCE_RAD of +y (a -y axis is turned)."""
    axis = _unit_axis(vector, source, key)
    # the spin axis has no physical sign, but the contact frame is built from it: take it
    # pointing left (+y) so that tyre moments do not depend on how the file wrote it
    axis = -axis if axis[1] < 0 else axis
    tilt = float(np.arccos(min(axis[1], 1.0)))
    if tilt > WHEEL_AXIS_TOLERANCE_RAD:
        raise ConfigError(source, key, f"the wheel axis {np.round(axis, 6).tolist()} is "
                                       f"{np.degrees(tilt):.4g} deg from the lateral axis; "
                                       f"allowed: within {WHEEL_AXIS_TOLERANCE_RAD:g} rad of "
                                       f"[0, 1, 0] or [0, -1, 0] (the engine linearizes about "
                                       f"upright, straight running)")
    return axis


def _unit_axis(vector, source, key):
    vector = np.asarray(vector, float)
    length = float(np.sqrt(vector @ vector))
    if length < 1e-12:
        raise ConfigError(source, key, "axis has zero length; give a non-zero direction")
    return vector / length


def _joint(name, spec, bodies, source):
    key = f"joints.{name}"
    for end in ("parent", "child"):
        if spec[end] not in bodies:
            raise ConfigError(source, f"{key}.{end}", f"unknown body '{spec[end]}' "
                                                      f"(bodies: {', '.join(bodies)})")
    return Joint(name, spec["type"], spec["parent"], spec["child"],
                 _unit_axis(spec["axis"], source, f"{key}.axis"),
                 np.asarray(spec["point"], float), spec["stiffness"], spec["damping"])


MIN_WHEELBASE_M = 0.1
"""Smallest distance [m] in x between the wheel centres (the wheel loads divide by it)."""


def _static_loads(bodies, wheel_specs, gravity, source):
    """Static vertical wheel loads [N] of a two-wheeler from the moment balance in x-z;
    ConfigError when the wheels are (nearly) at one x or a load is not positive."""
    masses = [(b.mass, b.com[0]) for b in bodies.values()]
    masses += [(w["mass"], w["centre"][0]) for w in wheel_specs.values()]
    weight = gravity * sum(m for m, _ in masses)
    moment = gravity * sum(m * x for m, x in masses)
    (name_a, wa), (name_b, wb) = wheel_specs.items()
    xa, xb = wa["centre"][0], wb["centre"][0]
    if abs(xb - xa) < MIN_WHEELBASE_M:
        raise ConfigError(source, f"wheels.{name_b}.centre",
                          f"the wheel centres are {abs(xb - xa):.3g} m apart in x; allowed: at "
                          f"least {MIN_WHEELBASE_M:g} m (the wheelbase)")
    load_b = (moment - weight * xa) / (xb - xa)
    loads = {name_a: weight - load_b, name_b: load_b}
    for name, load in loads.items():
        if not load > 0.0:
            raise ConfigError(source, "bodies", f"the static load on wheel '{name}' is "
                                                f"{load:.4g} N: the centre of mass "
                                                f"({moment / weight:.4g} m in x) is not "
                                                f"between the wheel centres")
    return loads


def _wheels(spec, bodies, source, gravity):
    specs = spec["wheels"]
    if len(specs) != 2:
        raise ConfigError(source, "wheels", f"expected 2 wheels, got {len(specs)}")
    loads = _static_loads(bodies, specs, gravity, source)
    wheels = []
    for name, w in specs.items():
        key = f"wheels.{name}"
        if w["carrier"] not in bodies:
            raise ConfigError(source, f"{key}.carrier", f"unknown body '{w['carrier']}'")
        if w["crown_radius"] >= w["radius"]:
            raise ConfigError(source, f"{key}.crown_radius",
                              f"crown radius {w['crown_radius']:g} m must be below the wheel "
                              f"radius {w['radius']:g} m")
        tyre = tyre_from_config(w["tyre"], source, f"{key}.tyre", loads[name], w["crown_radius"])
        axis = _lateral_axis(w["axis"], source, f"{key}.axis")
        wheels.append(Wheel(name, w["carrier"], np.asarray(w["centre"], float), axis, w["radius"],
                            w["crown_radius"], w["mass"], w["inertia"]["diametral"],
                            w["inertia"]["spin"], tyre))
    return tuple(wheels)


def vehicle_from_dict(data, source="<dict>"):
    """Validate a vehicle description (a dict shaped like the YAML) and build the model."""
    spec = validate(data, VEHICLE_SCHEMA, source)
    bodies = {name: _body(name, b, source) for name, b in spec["bodies"].items()}
    if spec["root"] not in bodies:
        raise ConfigError(source, "root", f"unknown body '{spec['root']}'")
    joints = tuple(_joint(n, j, bodies, source) for n, j in spec["joints"].items())
    for role, joint in spec["roles"].items():
        if joint not in {j.name for j in joints}:
            raise ConfigError(source, f"roles.{role}", f"unknown joint '{joint}'")
    wheels = _wheels(spec, bodies, source, spec["gravity"])
    return VehicleModel(spec["name"], str(source), spec["gravity"], spec["root"],
                        tuple(bodies.values()), joints, wheels, dict(spec["roles"]),
                        spec["reference_speed"], dict(spec["flex"]))


def load_vehicle(path):
    """Load and validate config/vehicles/<name>.yaml (a path) into a VehicleModel."""
    return vehicle_from_dict(load_yaml(path), Path(path))
