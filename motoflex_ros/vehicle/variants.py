"""The motorcycle variants' names and the flexible ground truth (superelements in place).

The variants themselves are built from identification results one layer up
(:func:`motoflex_ros.study.identified_variants.build_variant`): the vehicle takes lumped parameters
(:class:`~motoflex_ros.vehicle.lumped.FlexJoint`) and superelements, it does not read
identification results.
"""
from dataclasses import replace

from motoflex_ros.errors import ConfigError
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.superelement import chain_parts, end_body

__all__ = ["FLEX_CHOICES", "FLEXIBLE", "parse_components", "flexible_vehicle", "variant_label"]

FLEX_CHOICES = ("flexible", "flexible_bodies") + lumped.VARIANTS
"""``flexible``: one clamped superelement per component (the bench's reduced model);
``flexible_bodies``: the paper's per-body superelements joined by the vehicle's joints
(:mod:`motoflex_ros.vehicle.flexible_motorcycle`); then the lumped variants."""
FLEXIBLE = ("flexible", "flexible_bodies")


def parse_components(names, source="--component"):
    """Component names from a list (repeatable ``--component``) or a comma-separated text; None,
    empty or 'all' = the three motorcycle components."""
    if isinstance(names, str):
        names = names.split(",")
    names = [n.strip() for n in (names or []) if n.strip()]
    if names in ([], ["all"]):
        return list(lumped.COMPONENTS)
    for name in names:
        if name not in lumped.COMPONENTS:
            raise ConfigError(source, "components", f"unknown component '{name}' (allowed: "
                                                    f"{', '.join(lumped.COMPONENTS)}, all)")
    return names


def variant_label(variant, names):
    """How a report names a variant: 'rigid', 'flexible frame, swingarm' or "lumped 'static'
    variant of frame, front_assembly, swingarm"."""
    if variant == "rigid" or not names:
        return "rigid"
    if variant == "flexible":
        return f"flexible {', '.join(names)}"
    if variant == "flexible_bodies":
        return f"flexible bodies of {', '.join(names)}"
    return f"lumped '{variant}' variant of {', '.join(names)}"


def flexible_vehicle(vehicle, superelements):
    """The rigid vehicle with each component's superelement in place (the ground truth).

    ``superelements`` maps a component name to its Superelement (welded to the body of
    :data:`lumped.SUPERELEMENT_PARENT`); what the component carries hangs from the
    superelement's end body.
    """
    bodies = list(vehicle.bodies)
    joints = list(vehicle.joints)
    wheels = list(vehicle.wheels)
    for component, se in superelements.items():
        new_bodies, new_joints = chain_parts(se)
        bodies += new_bodies
        joints += new_joints
        lumped.reattach(vehicle, component, joints, wheels, end_body(se))
    flex = {**vehicle.flex, "variant": "flexible", "components": tuple(superelements)}
    return replace(vehicle, name=f"{vehicle.name}+flexible", bodies=tuple(bodies),
                   joints=tuple(joints), wheels=tuple(wheels),
                   elements=vehicle.elements + tuple(superelements.values()), flex=flex)
