"""The outline of a motorcycle's bodies a viewer draws (the rerun recording, the bag's
/vehicle/geometry markers): where each body holds its joints and wheels. Numbers only, no
engine: :mod:`motoflex_ros.record` may import it directly.
"""
import numpy as np

__all__ = ["body_attachments"]


def body_attachments(model):
    """{body: [points [m] in the vehicle frame at rest]}: its joints' points and the centres of
    the wheels it carries (what a viewer draws a body's linkage to)."""
    points = {b.name: [] for b in model.bodies}
    for joint in model.joints:
        for body in (joint.parent, joint.child):
            if body in points:
                points[body].append(np.asarray(joint.point, float))
    for wheel in model.wheels:
        if wheel.carrier in points:
            points[wheel.carrier].append(np.asarray(wheel.centre, float))
    return points
