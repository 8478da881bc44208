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
from motoflex_ros.inertia import check_inertia, composite_inertia, inertia_matrix
from motoflex_ros.vehicle.schema import LOOP_CLOSURE_TOLERANCE, REFERENCE_SPEED, VEHICLE_SCHEMA
from motoflex_ros.vehicle.tyre import tyre_from_config

__all__ = ["Body", "Joint", "Wheel", "VehicleModel", "load_vehicle", "vehicle_from_dict",
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

    kind 'revolute' or 'prismatic' adds one coordinate, 'universal' two (rotations about axis,
    then axis2), 'spherical' three (about axis, axis2, axis x axis2), 'fixed' none; a joint
    that closes a loop adds constraints instead (:mod:`motoflex_ros.vehicle.loops`).
    stiffness [N m/rad] (or [N/m]) and damping [N m s/rad] act on the (first) joint coordinate.
    locked: the coordinate is frozen at 0 (one constraint), e.g. suspension travel.
    cut: the joint always closes a loop (a cut joint, constraint rows only): it is applied
    after every tree joint, so its two bodies may be reached in any order (a superelement's
    end body at the end of its six-joint chain, a bushing's end body closed onto another body).
    """

    name: str
    kind: str
    parent: str
    child: str
    axis: np.ndarray
    point: np.ndarray
    stiffness: float = 0.0
    damping: float = 0.0
    axis2: np.ndarray = None
    locked: bool = False
    cut: bool = False

    @property
    def axes(self):
        """Unit rotation axes of the joint's coordinates, in order (revolute: axis; universal:
        axis, axis2; spherical: axis, axis2, axis x axis2; prismatic: the sliding axis)."""
        if self.kind in ("revolute", "prismatic", "modal"):
            return (self.axis,)
        if self.kind == "universal":
            return (self.axis, self.axis2)
        if self.kind == "spherical":
            return (self.axis, self.axis2, np.cross(self.axis, self.axis2))
        return ()


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
    reference_speed [m/s] is where weave, wobble and capsize are named before tracking;
    base 'floating' (a vehicle on its wheels) or 'fixed' (the root body is the ground: a
    mechanism on a stand, no wheels).

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
    base: str = "floating"

    def body(self, name):
        """The body called ``name``."""
        return next(b for b in self.bodies if b.name == name)

    def total_mass(self):
        """Sum of body and wheel masses [kg]."""
        return sum(b.mass for b in self.bodies) + sum(w.mass for w in self.wheels)


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


def _second_axis(axis, spec, source, key):
    """Unit second axis of a universal or spherical joint, made normal to ``axis``: the given
    axis2 (Gram-Schmidt), else the normal to axis nearest to the lateral (then vertical) one."""
    given = spec["axis2"]
    trial = np.asarray(given, float) if given is not None else np.array([0.0, 1.0, 0.0])
    if given is None and abs(axis @ trial) > 0.9:
        trial = np.array([0.0, 0.0, 1.0])
    normal = trial - (trial @ axis) * axis
    if np.linalg.norm(normal) < 1e-6 * max(np.linalg.norm(trial), 1e-300):
        raise ConfigError(source, f"{key}.axis2", "parallel to axis (or zero); give a "
                                                 "direction not parallel to axis")
    return normal / np.linalg.norm(normal)


def _joint(name, spec, bodies, source):
    key = f"joints.{name}"
    for end in ("parent", "child"):
        if spec[end] not in bodies:
            raise ConfigError(source, f"{key}.{end}", f"unknown body '{spec[end]}' "
                                                      f"(bodies: {', '.join(bodies)})")
    if spec["parent"] == spec["child"]:
        raise ConfigError(source, f"{key}.child", f"the joint joins body '{spec['child']}' to "
                                                  "itself; give two different bodies")
    kind = spec["type"]
    axis = _unit_axis(spec["axis"], source, f"{key}.axis")
    axis2 = _second_axis(axis, spec, source, key) if kind in ("universal", "spherical") else None
    if spec["axis2"] is not None and axis2 is None:
        raise ConfigError(source, f"{key}.axis2", f"only a universal or spherical joint has a "
                                                 f"second axis (this one is {kind})")
    if spec["locked"] and kind not in ("revolute", "prismatic"):
        raise ConfigError(source, f"{key}.locked", f"only a revolute or prismatic coordinate can "
                                                   f"be locked (this joint is {kind}; a locked "
                                                   "joint of another kind is a fixed joint)")
    point = np.asarray(spec["point"], float)
    if spec["child_point"] is not None:
        gap = float(np.linalg.norm(np.asarray(spec["child_point"], float) - point))
        if gap > LOOP_CLOSURE_TOLERANCE:
            raise ConfigError(source, f"{key}.child_point",
                              f"the joint cannot close: its child's point is {gap * 1e3:.3g} mm "
                              f"from its parent's point {np.round(point, 6).tolist()} m "
                              f"(allowed: within {LOOP_CLOSURE_TOLERANCE * 1e3:g} mm)")
    return Joint(name, kind, spec["parent"], spec["child"], axis, point, spec["stiffness"],
                 spec["damping"], axis2, bool(spec["locked"]))


MIN_WHEELBASE_M = 0.1
"""Smallest distance [m] in x between the wheel centres (the wheel loads divide by it)."""


def _static_loads(bodies, wheel_specs, gravity, source="<dict>"):
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
    if spec["base"] == "fixed":
        if specs:
            raise ConfigError(source, "wheels", "a fixed-base mechanism (base: fixed) has no "
                                                f"wheels; got {len(specs)}")
        return ()
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
                        spec["reference_speed"], dict(spec["flex"]), base=spec["base"])


def load_vehicle(path):
    """Load and validate config/vehicles/<name>.yaml (a path) into a VehicleModel."""
    return vehicle_from_dict(load_yaml(path), Path(path))
