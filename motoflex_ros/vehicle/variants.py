"""Build a motorcycle variant from the rigid vehicle, the components and the identification.

``build_variant(vehicle, variant, names, identified, components)`` gives the VehicleModel of one
of the paper's variants (Sect. 5.2) with the flexibility of the components ``names`` (a subset
of frame, front_assembly, swingarm): ``rigid``, ``flexible`` (Craig-Bampton superelements,
:mod:`motoflex_ros.vehicle.superelement`), the lumped ``state_of_the_art``, ``static``,
``torsion``, ``bending`` and ``decomposed`` models (:mod:`motoflex_ros.vehicle.lumped`).
``components`` maps a component name to its structures Component (placement, loaded end, the
clamped finite-element model for the state-of-the-art static moment test).
"""
from dataclasses import replace

from motoflex_ros.errors import ConfigError
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.superelement import chain_parts, end_body, superelement_of

__all__ = ["FLEX_CHOICES", "parse_components", "build_variant", "flexible_vehicle",
           "variant_label"]

FLEX_CHOICES = ("flexible",) + lumped.VARIANTS


def parse_components(text, source="--components"):
    """Component names from a comma-separated list ('all' = the three motorcycle components)."""
    if text in (None, "", "all"):
        return list(lumped.COMPONENTS)
    names = [n.strip() for n in text.split(",") if n.strip()]
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
    return f"lumped '{variant}' variant of {', '.join(names)}"


def _steer_axis(vehicle):
    role = vehicle.roles.get("steer", "steer")
    return next(j.axis for j in vehicle.joints if j.name == role)


def build_variant(vehicle, variant, names, identified, components):
    """VehicleModel of ``variant`` with the lumped flexibility of the components ``names``."""
    if variant not in FLEX_CHOICES:
        raise ConfigError("--flex", "variant", f"'{variant}' is not one of: "
                                               f"{', '.join(FLEX_CHOICES)}")
    if variant == "rigid":
        return vehicle
    if variant == "flexible":
        for name in names:
            lumped.check_site(vehicle, name, lumped.site_of(components[name]))
        return flexible_vehicle(vehicle, {
            name: superelement_of(components[name], lumped.SUPERELEMENT_PARENT[name])
            for name in names})
    joints = {}
    for name in names:
        site = lumped.site_of(components[name])
        lumped.check_site(vehicle, name, site)
        sota = None
        if variant == "state_of_the_art":
            point, axis = lumped.state_of_the_art_axis(name, site, _steer_axis(vehicle))
            reduced = components[name].clamped_reduced()
            k = lumped.state_of_the_art_stiffness(reduced, axis, point - site.origin,
                                                  lumped.SOTA_LOAD[name])
            sota = (point, axis, k)
        joints[name] = lumped.flex_joints(variant, name, identified, site, sota)
    return lumped.lumped_vehicle(vehicle, variant, joints)


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
