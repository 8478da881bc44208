"""YAML schema of a vehicle description (config/vehicles/*.yaml).

Lengths in m, masses in kg, inertias in kg m^2 (tensor entries about the centre of mass in the
reference configuration, REP-103 axes, so a product entry is -integral(x z dm)), stiffness in
N m/rad, damping in N m s/rad, gravity in m/s^2.
"""
from motoflex_ros.config import Field, number, positive
from motoflex_ros.units import kmh_to_ms

__all__ = ["VEHICLE_SCHEMA", "TYRE_SCHEMAS", "REFERENCE_SPEED", "MF_COEFFICIENTS", "JOINT_TYPES",
           "LOOP_CLOSURE_TOLERANCE"]

LOOP_CLOSURE_TOLERANCE = 1e-3
"""Largest distance [m] between a joint's point and its child_point; further apart the loop
cannot close."""

_INERTIA = Field("mapping", fields={
    "xx": positive(), "yy": positive(), "zz": positive(),
    "xy": number(required=False, default=0.0), "xz": number(required=False, default=0.0),
    "yz": number(required=False, default=0.0),
}, help="mapping xx, yy, zz [, xy, xz, yz] [kg m^2]")

_PART = Field("mapping", fields={
    "mass": positive(help="mass [kg]"),
    "com": Field("vec3"),
    "inertia": _INERTIA,
    "source": Field("str", required=False, default=""),
})

_BODY = Field("mapping", fields={
    "mass": number(0.0, required=False, help="mass [kg]"),
    "com": Field("vec3", required=False),
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
    "axis": Field("vec3", required=False, default=[1.0, 0.0, 0.0]),
    "axis2": Field("vec3", required=False, default=None,
                   help="second axis of a universal or spherical joint (default: a unit vector "
                        "normal to axis)"),
    "point": Field("vec3", required=False, default=[0.0, 0.0, 0.0]),
    "child_point": Field("vec3", required=False, default=None,
                         help="the child's attachment point [m] when it is given apart from "
                              "point (e.g. from the child's own drawing); within 1 mm of point"),
    "locked": Field("bool", required=False, default=False,
                    help="frozen coordinate (e.g. suspension travel at the riding point): the "
                         "joint keeps its kinematics in the loop, its coordinate stays 0"),
    "stiffness": number(0.0, required=False, default=0.0, help="[N m/rad]"),
    "damping": number(0.0, required=False, default=0.0, help="[N m s/rad]"),
    "source": Field("str", required=False, default=""),
})

_WHEEL = Field("mapping", fields={
    "carrier": Field("str"),
    "centre": Field("vec3"),
    "axis": Field("vec3", required=False, default=[0.0, 1.0, 0.0]),
    "radius": positive(help="rolling radius [m]"),
    "crown_radius": number(0.0, required=False, default=0.0, help="[m], below radius"),
    "mass": positive(),
    "inertia": Field("mapping", fields={"diametral": positive(), "spin": positive()}),
    "tyre": Field("mapping", extra=True, fields={
        "model": Field("str", choices=("knife_edge", "linear", "magic_formula"))}),
    "source": Field("str", required=False, default=""),
})

REFERENCE_SPEED = float(kmh_to_ms(100.0))  # [m/s] where modes are named unless the file says

VEHICLE_SCHEMA = Field("mapping", fields={
    "name": Field("str"),
    "description": Field("str", required=False, default=""),
    "gravity": positive(required=False, default=9.81, help="[m/s^2]"),
    "root": Field("str", help="name of the floating-base body"),
    "base": Field("str", required=False, default="floating", choices=("floating", "fixed"),
                  help="floating: a vehicle on its wheels; fixed: the root body is the ground "
                       "(a mechanism on a test stand, no wheels)"),
    "reference_speed": positive(required=False, default=REFERENCE_SPEED,
                                help="speed [m/s] at which modes are named before tracking"),
    "roles": Field("mapping", required=False, default={}, extra=True, item=Field("str")),
    "bodies": Field("mapping", extra=True, item=_BODY, min_items=1),
    "joints": Field("mapping", required=False, default={}, extra=True, item=_JOINT),
    "wheels": Field("mapping", required=False, default={}, extra=True, item=_WHEEL),
    "flex": Field("mapping", required=False, default={}, extra=True,
                  help="reserved for lumped/flexible variants (added by the accuracy issue)"),
})

_RELAXATION = {"relaxation_length": positive(help="[m]")}

MF_COEFFICIENTS = ("Cy", "pdy1", "pdy2", "pdy3", "pey1", "pey2", "pey4", "pky1", "pky2", "pky3",
                   "pky4", "pky5", "pky6", "pky7", "Cgamma", "Egamma", "Ct", "qbz1", "qbz2",
                   "qbz5", "qbz6", "qbz9", "qbz10", "qdz1", "qdz2", "qdz3", "qdz4", "qdz8",
                   "qdz9", "qdz10", "qdz11", "qez1", "qez2", "qez5", "qhz3", "qhz4")
"""Pure-slip side force and aligning moment coefficients of the motorcycle Magic Formula that
:mod:`motoflex_ros.vehicle.tyre` uses (reference/motorcycle-data.md sect. 1.1-1.2, names as in
[MD]); the combined-slip and longitudinal ones (rby*, Cyk...) are not modelled. All are required
(missing ones are listed together by ``tyre_from_config``); any other key is refused."""

TYRE_SCHEMAS = {
    "knife_edge": Field("mapping", fields={"model": Field("str")}),
    "linear": Field("mapping", fields={
        "model": Field("str"),
        "cornering_stiffness": positive(help="[N/rad]"),
        "camber_stiffness": number(0.0, required=False, default=0.0, help="[N/rad]"),
        "aligning_stiffness": number(required=False, default=0.0, help="[N m/rad]"),
        "twisting_stiffness": number(required=False, default=0.0, help="[N m/rad]"),
        **_RELAXATION,
    }),
    "magic_formula": Field("mapping", fields={
        "model": Field("str"),
        **{name: number(required=False, default=None, help="Magic Formula coefficient")
           for name in MF_COEFFICIENTS},
        "Fz0": positive(help="nominal load [N]"),
        "relaxation_a": positive(help="lateral compliance coefficient [m/N]"),
        "relaxation_b": number(help="[s/N]"),
        "relaxation_c": number(help="[s^2/(m N)]"),
    }),
}
