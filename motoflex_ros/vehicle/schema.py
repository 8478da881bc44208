"""YAML schema of a vehicle description (config/vehicles/*.yaml).

Lengths in m, masses in kg, inertias in kg m^2 (tensor entries about the centre of mass in the
reference configuration, REP-103 axes, so a product entry is -integral(x z dm)), stiffness in
N m/rad, damping in N m s/rad, gravity in m/s^2.
"""
from motoflex_ros.config import Field, number, positive
from motoflex_ros.units import kmh_to_ms

__all__ = ["VEHICLE_SCHEMA", "TYRE_SCHEMAS", "REFERENCE_SPEED", "MF_COEFFICIENTS", "JOINT_TYPES",
           "LOOP_CLOSURE_TOLERANCE", "SPEED_MAX_MPS"]

LOOP_CLOSURE_TOLERANCE = 1e-3
"""Largest distance [m] between a joint's point and its child_point; further apart the loop
cannot close."""

# Physical ranges of every number (SI): any two-wheeler with its rider and luggage fits in
# them; beyond them the linearization overflows or a wrong value is blamed on another key (a
# mass of 1e300 kg came out as a negative tyre cornering stiffness, key pky1).
MASS_MAX_KG = 1e4
INERTIA_MAX = 1e4  # [kg m^2]
SIZE_M = 10.0  # coordinates [m]
WHEEL_MASS_MAX_KG = 1e3
WHEEL_INERTIA_MAX = 1e3  # [kg m^2]
WHEEL_RADIUS_M = (0.01, 2.0)
JOINT_STIFFNESS_MAX = 1e10  # [N m/rad] or [N/m]
JOINT_DAMPING_MAX = 1e8  # [N m s/rad] or [N s/m]
TYRE_STIFFNESS_MAX = 1e12  # [N/rad], [N m/rad]; 1e10 is a tyre at its knife-edge limit
MF_COEFFICIENT_MAX = 1e4  # |coefficient| of the Magic Formula (dimensionless or per unit)
SPEED_MAX_MPS = float(kmh_to_ms(400.0))  # [m/s] fastest speed of a sweep or a road test

_POINT = Field("vec3", -SIZE_M, SIZE_M)
_AXIS = Field("vec3", -1e3, 1e3, required=False, default=[1.0, 0.0, 0.0])
_INERTIA = Field("mapping", fields={
    "xx": positive(INERTIA_MAX), "yy": positive(INERTIA_MAX), "zz": positive(INERTIA_MAX),
    "xy": number(-INERTIA_MAX, INERTIA_MAX, required=False, default=0.0),
    "xz": number(-INERTIA_MAX, INERTIA_MAX, required=False, default=0.0),
    "yz": number(-INERTIA_MAX, INERTIA_MAX, required=False, default=0.0),
}, help="mapping xx, yy, zz [, xy, xz, yz] [kg m^2]")

_PART = Field("mapping", fields={
    "mass": positive(MASS_MAX_KG, help="mass [kg]"),
    "com": _POINT,
    "inertia": _INERTIA,
    "source": Field("str", required=False, default=""),
})

_BODY = Field("mapping", fields={
    "mass": number(0.0, MASS_MAX_KG, required=False, help="mass [kg]"),
    "com": Field("vec3", -SIZE_M, SIZE_M, required=False),
    "inertia": Field("mapping", required=False, fields=_INERTIA.fields),
    "parts": Field("mapping", required=False, extra=True, item=_PART),
    "source": Field("str", required=False, default=""),
})

JOINT_TYPES = ("revolute", "prismatic", "fixed", "universal", "spherical")
"""Joint kinds. revolute / prismatic: one coordinate about / along ``axis``; universal: two
rotations, about ``axis`` then ``axis2``; spherical: three rotations, about ``axis``, ``axis2``
and axis x axis2 (so a spherical joint's first coordinate can be a named role, e.g. the
steering angle about the axis through two spherical joints); fixed: none. A joint whose child
is already attached closes a kinematic loop (a cut joint): it adds constraint equations
instead of coordinates."""

_JOINT = Field("mapping", fields={
    "type": Field("str", choices=JOINT_TYPES),
    "parent": Field("str"),
    "child": Field("str"),
    "axis": _AXIS,
    "axis2": Field("vec3", -1e3, 1e3, required=False, default=None,
                   help="second axis of a universal or spherical joint (default: a unit vector "
                        "normal to axis)"),
    "point": Field("vec3", -SIZE_M, SIZE_M, required=False, default=[0.0, 0.0, 0.0]),
    "child_point": Field("vec3", -SIZE_M, SIZE_M, required=False, default=None,
                         help="the child's attachment point [m] when it is given apart from "
                              "point (e.g. from the child's own drawing); within 1 mm of point"),
    "locked": Field("bool", required=False, default=False,
                    help="frozen coordinate (e.g. suspension travel at the riding point): the "
                         "joint keeps its kinematics in the loop, its coordinate stays 0"),
    "stiffness": number(0.0, JOINT_STIFFNESS_MAX, required=False, default=0.0,
                        help="[N m/rad]"),
    "damping": number(0.0, JOINT_DAMPING_MAX, required=False, default=0.0,
                      help="[N m s/rad]"),
    "source": Field("str", required=False, default=""),
})

_WHEEL = Field("mapping", fields={
    "carrier": Field("str"),
    "centre": _POINT,
    "axis": Field("vec3", -1e3, 1e3, required=False, default=[0.0, 1.0, 0.0]),
    "radius": number(*WHEEL_RADIUS_M, help="rolling radius [m]"),
    "crown_radius": number(0.0, WHEEL_RADIUS_M[1], required=False, default=0.0,
                           help="[m], below radius"),
    "mass": positive(WHEEL_MASS_MAX_KG),
    "inertia": Field("mapping", fields={"diametral": positive(WHEEL_INERTIA_MAX),
                                        "spin": positive(WHEEL_INERTIA_MAX)}),
    "tyre": Field("mapping", extra=True, fields={
        "model": Field("str", choices=("knife_edge", "linear", "magic_formula"))}),
    "source": Field("str", required=False, default=""),
})

REFERENCE_SPEED = float(kmh_to_ms(100.0))  # [m/s] where modes are named unless the file says

VEHICLE_SCHEMA = Field("mapping", fields={
    "name": Field("str"),
    "description": Field("str", required=False, default=""),
    "gravity": positive(100.0, required=False, default=9.81, help="[m/s^2]"),
    "root": Field("str", help="name of the floating-base body"),
    "base": Field("str", required=False, default="floating", choices=("floating", "fixed"),
                  help="floating: a vehicle on its wheels; fixed: the root body is the ground "
                       "(a mechanism on a test stand, no wheels)"),
    "reference_speed": positive(SPEED_MAX_MPS, required=False, default=REFERENCE_SPEED,
                                help="speed [m/s] at which modes are named before tracking"),
    "roles": Field("mapping", required=False, default={}, extra=True, item=Field("str")),
    "bodies": Field("mapping", extra=True, item=_BODY, min_items=1),
    "joints": Field("mapping", required=False, default={}, extra=True, item=_JOINT),
    "wheels": Field("mapping", required=False, default={}, extra=True, item=_WHEEL),
    "flex": Field("mapping", required=False, default={}, extra=True,
                  help="reserved for lumped/flexible variants (added by the accuracy issue)"),
})

_RELAXATION = {"relaxation_length": positive(10.0, help="[m]")}

MF_COEFFICIENTS = ("Cy", "pdy1", "pdy2", "pdy3", "pey1", "pey2", "pey4", "pky1", "pky2", "pky3",
                   "pky4", "pky5", "pky6", "pky7", "Cgamma", "Egamma", "Ct", "qbz1", "qbz2",
                   "qbz5", "qbz6", "qbz9", "qbz10", "qdz1", "qdz2", "qdz3", "qdz4", "qdz8",
                   "qdz9", "qdz10", "qdz11", "qez1", "qez2", "qez5", "qhz3", "qhz4")
"""Pure-slip side force and aligning moment coefficients of the motorcycle Magic Formula that
:mod:`motoflex_ros.vehicle.tyre` uses ([MD] and [TUM] in docs/references.md, names as in
[MD]); the combined-slip and longitudinal ones (rby*, Cyk...) are not modelled. All are required
(missing ones are listed together by ``tyre_from_config``); any other key is refused."""

TYRE_SCHEMAS = {
    "knife_edge": Field("mapping", fields={"model": Field("str")}),
    "linear": Field("mapping", fields={
        "model": Field("str"),
        "cornering_stiffness": positive(TYRE_STIFFNESS_MAX, help="[N/rad]"),
        "camber_stiffness": number(0.0, TYRE_STIFFNESS_MAX, required=False, default=0.0,
                                   help="[N/rad]"),
        "aligning_stiffness": number(-TYRE_STIFFNESS_MAX, TYRE_STIFFNESS_MAX, required=False,
                                     default=0.0, help="[N m/rad]"),
        "twisting_stiffness": number(-TYRE_STIFFNESS_MAX, TYRE_STIFFNESS_MAX, required=False,
                                     default=0.0, help="[N m/rad]"),
        **_RELAXATION,
    }),
    "magic_formula": Field("mapping", fields={
        "model": Field("str"),
        **{name: number(-MF_COEFFICIENT_MAX, MF_COEFFICIENT_MAX, required=False, default=None,
                        help="Magic Formula coefficient")
           for name in MF_COEFFICIENTS},
        "Fz0": number(10.0, 1e5, help="nominal load [N]"),   # the formula divides by it
        "relaxation_a": positive(1.0, help="lateral compliance coefficient [m/N]"),
        "relaxation_b": number(-1.0, 1.0, help="[s/N]"),
        "relaxation_c": number(-1.0, 1.0, help="[s^2/(m N)]"),
    }),
}
