"""Messages a 3D or plot panel draws that no other node module builds: the motorcycle's body
geometry (visualization_msgs/MarkerArray on its /tf frames) and a bench sample's phase as
numbers (sensor_msgs/JointState, one named value each).

Numbers and names come from the core (:func:`motoflex_ros.vehicle.outline.body_attachments`,
the model's wheels); this module only builds messages.
"""
import numpy as np
from geometry_msgs.msg import Point
from std_msgs.msg import Header
from visualization_msgs.msg import Marker, MarkerArray

from motoflex_ros.frames import body_frame
from motoflex_ros.nodes.conversions import joint_state_msg
from motoflex_ros.nodes.stamps import time_msg
from motoflex_ros.vehicle.outline import body_attachments

__all__ = ["PHASE_CODES", "PHASE_VALUE_NAMES", "phase_values_msg", "motorcycle_markers"]

PHASE_CODES = {"ramp": 1, "hold": 2, "preload": 3, "release": 4, "onset": 5, "steady": 6}
"""The number of each phase of a bench test on /bench/<c>/phase_values (0: between tests)."""
PHASE_VALUE_NAMES = ["test", "phase", "frequency_hz", "load"]
TUBE_M = 0.03          # width of the linkage lines [m]
RING_POINTS = 36
_GREY, _TYRE = (0.6, 0.6, 0.68), (0.15, 0.15, 0.15)


def phase_values_msg(ns, test_number, sample):
    """sensor_msgs/JointState at ``ns`` [ns]: name PHASE_VALUE_NAMES, position [the test's
    number in the campaign (1-based), PHASE_CODES of its phase, frequency [Hz] (0: none), the
    commanded amplitude [N or N m]]."""
    values = [float(test_number), float(PHASE_CODES.get(sample.phase, 0)),
              float(sample.frequency_hz), float(sample.force)]
    zeros = [0.0] * len(values)   # filled: see joint_state_msg
    return joint_state_msg(ns, PHASE_VALUE_NAMES, values, zeros, zeros)


def _header(ns, frame_id):
    return Header(stamp=time_msg(ns), frame_id=frame_id)


def _marker(ns, frame, name, marker_id, kind, points, color, width):
    marker = Marker(header=_header(ns, frame), ns=name, id=marker_id, type=kind,
                    action=Marker.ADD, frame_locked=True)
    marker.pose.orientation.w = 1.0
    marker.scale.x = marker.scale.y = marker.scale.z = width
    marker.color.r, marker.color.g, marker.color.b = color
    marker.color.a = 1.0
    marker.points = [Point(x=float(x), y=float(y), z=float(z)) for x, y, z in points]
    return marker


def _ring(centre, axis, radius):
    """RING_POINTS + 1 points [m] of a circle of ``radius`` about ``axis`` through ``centre``."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    e1 = np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    phi = np.linspace(0.0, 2.0 * np.pi, RING_POINTS + 1)
    return centre + radius * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)


def _drawn_on(model, name):
    """The body with mass a wheel's carrier ``name`` moves with: the carrier itself, or (a
    massless carrier, as a lumped variant's flexible joint body) its nearest parent with mass
    along the joints."""
    masses = {b.name: b.mass for b in model.bodies}
    parents = {j.child: j.parent for j in model.joints}
    while masses.get(name, 0.0) <= 0 and name in parents:
        name = parents[name]
    return name


def motorcycle_markers(model, ns):
    """visualization_msgs/MarkerArray of the bodies with mass at ``ns`` [ns], each in its frame
    vehicle/<body> (origin at its centre of mass, the reference axes; frame_locked, so they
    move with /tf): lines from the centre of mass to each joint and wheel centre it holds
    (frame, fork, Telelever arm, swingarm, strut as the linkage they are), a sphere at the
    centre of mass and each wheel's tyre as a ring on its carrier [m]."""
    attached = body_attachments(model)
    markers = []
    for body in (b for b in model.bodies if b.mass > 0):
        com = np.asarray(body.com, float)
        frame = body_frame(body.name)
        ends = [p - com for p in attached[body.name]]
        lines = [q for p in ends for q in (np.zeros(3), p)]
        if lines:
            markers.append(_marker(ns, frame, f"{body.name}/links", 0, Marker.LINE_LIST,
                                   lines, _GREY, TUBE_M))
        markers.append(_marker(ns, frame, f"{body.name}/com", 0, Marker.SPHERE_LIST,
                               [np.zeros(3)], _GREY, 2 * TUBE_M))
        for k, wheel in enumerate(w for w in model.wheels
                                  if _drawn_on(model, w.carrier) == body.name):
            markers.append(_marker(ns, frame, f"{body.name}/wheel", k, Marker.LINE_STRIP,
                                   _ring(np.asarray(wheel.centre, float) - com, wheel.axis,
                                         wheel.radius), _TYRE, 2 * TUBE_M))
    return MarkerArray(markers=markers)
