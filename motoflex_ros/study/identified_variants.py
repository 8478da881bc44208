"""Motorcycle variants from identification results: the paper's lumped models (Sect. 5.2).

``build_variant(vehicle, variant, names, identified, components)`` gives the VehicleModel of one
of the paper's variants with the flexibility of the components ``names`` (a subset of frame,
front_assembly, swingarm): ``rigid``, ``flexible`` (Craig-Bampton superelements,
:mod:`motoflex_ros.vehicle.superelement`), the lumped ``state_of_the_art``, ``static``,
``torsion``, ``bending`` and ``decomposed`` models (:mod:`motoflex_ros.vehicle.lumped`), and
the single hinges of ``HINGE_VARIANTS`` (``fitted``, ``road_load``, ``vehicle_load``: a
static-like model whose l, beta, k the results carry under that name, e.g. from
:meth:`motoflex_ros.study.hinge_fit_result.HingeFit.identified`).
``identified`` is the identification of the bench campaign (the JSON of ``motoflex identify``);
``components`` maps a component name to its structures Component (placement, loaded end, the
clamped finite-element model for the state-of-the-art static test). This is where
identification, structures and vehicle meet; the vehicle itself only takes lumped joints.
"""
import numpy as np

from motoflex_ros.config import number_text, resolve_config, shown
from motoflex_ros.errors import ConfigError, ModelError, MotoflexError
from motoflex_ros.identify.principal import CarriedInertia
from motoflex_ros.identify.results import results_source
from motoflex_ros.identify.stiffness import GAMMA_S
from motoflex_ros.lumped_stiffness.axis import axis_stiffness
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.flexible_motorcycle import per_body_vehicle
from motoflex_ros.vehicle.lumped import HINGE_VARIANTS, VARIANTS, FlexJoint, axis_in_vehicle
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.superelement import superelement_of
from motoflex_ros.vehicle.variants import FLEX_CHOICES, FLEXIBLE, flexible_vehicle

__all__ = ["build_variant", "flex_joints", "check_split_identifiable", "check_principal",
           "state_of_the_art_stiffness", "carried_of", "carried_by_component",
           "carried_inertias", "SOTA_LOAD", "GAMMA", "SERIES_VARIANTS"]

GAMMA = GAMMA_S
"""Proportionality constant of the static models' damping c = gamma k [s] (Sect. 5.2.4)."""


SERIES_VARIANTS = ("decomposed", "principal")
"""Variants of hinges in series at the loaded end (c = gamma k, the static model's inertia
distribution): eq. (12)'s torsion and bending hinges, and the principal hinges
(:mod:`motoflex_ros.identify.principal`)."""


SOTA_LOAD = {"frame": "moment", "front_assembly": "lateral_force", "swingarm": "moment"}
"""How the literature measures each component's stiffness (Sect. 5.2.1-5.2.3): a static moment
about the joint axis (frame: at the steering head; swingarm: parallel to x at the wheel axis) or
a static lateral force at the wheel axis (front assembly, after [11])."""


def state_of_the_art_stiffness(reduced, axis, point=None, load="moment"):
    """Stiffness [N m/rad] of the literature's joint from a static test on the clamped model.

    ``load="moment"``: a moment about ``axis`` at the loaded end divided by the end's rotation
    about it, k = 1 / (a^T theta(a)), theta(a) [rad] under a unit moment [N m].
    ``load="lateral_force"``: eq. (8) with a lateral force F_y at q0 and the arm b [m] of q0
    about the axis through ``point`` (component frame), k = F b / asin(y_q / b).
    """
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    if load == "moment":
        motion = reduced.static_end_motion(np.concatenate([np.zeros(3), a]))
        return float(1.0 / (a @ motion[3:]))
    force = 1.0
    motion = reduced.static_end_motion([0.0, force, 0.0, 0.0, 0.0, 0.0])
    r = reduced.q0 - np.asarray(point, float)
    arm = float(np.linalg.norm(r - (r @ a) * a))
    return float(axis_stiffness(force, motion[1], arm))


def check_split_identifiable(identified, component):
    """Raise ModelError naming the component if its eq. (12) split k_t, k_b is not identifiable.

    The identification marks it (``split_identifiable`` False, ``split_problem`` the reason,
    k_t and k_b null/NaN); a result file without the mark is judged by its values: a missing,
    non-finite or non-positive k_t or k_b cannot be a spring of the decomposed variant.
    """
    result = identified.get(component) if isinstance(identified, dict) else None
    if not isinstance(result, dict):
        return
    problem = result.get("split_problem")
    values = {key: result.get(key) for key in ("k_t", "k_b") if key in result}
    bad = [f"{component}.{key} = {_show(value)}" for key, value in values.items()
           if isinstance(value, bool) or not isinstance(value, (int, float))
           or not np.isfinite(value) or value <= 0]
    if result.get("split_identifiable") is False or bad:
        raise ModelError(f"{results_source(identified)}: component '{component}': its "
                         f"torsion/bending split (eq. 12) is not identifiable "
                         f"({problem or ', '.join(bad)}); the decomposed variant needs "
                         f"positive k_t and k_b, use the static, torsion or bending variant")


def check_principal(identified, component):
    """Raise ModelError naming the component if its principal hinges were not identified
    (``principal.identified`` False: the reason is in ``principal.problem``)."""
    result = identified.get(component) if isinstance(identified, dict) else None
    principal = result.get("principal") if isinstance(result, dict) else None
    if isinstance(principal, dict) and principal.get("identified") is False:
        raise ModelError(f"{results_source(identified)}: component '{component}': its "
                         f"principal hinges are not identified ({principal.get('problem')}); "
                         f"the principal variant needs them")


def carried_of(vehicle, component, site):
    """CarriedInertia (component frame) of what ``component``'s loaded end carries in the
    vehicle (:data:`motoflex_ros.vehicle.lumped.CARRIED`): the principal hinges' metric in
    the virtual rig."""
    mass, com, inertia, passes, names = lumped.carried_inertia(vehicle, component)
    return CarriedInertia(mass, np.asarray(com, float) - site.origin, inertia, passes,
                          f"vehicle '{vehicle.name}': {', '.join(names)}")


def carried_by_component(vehicle, components):
    """{name: CarriedInertia} of the motorcycle components among ``components`` ({name:
    structures Component}) placed in ``vehicle``."""
    return {name: carried_of(vehicle, name, lumped.site_of(component))
            for name, component in components.items() if name in lumped.CARRIED}


def carried_inertias(components, vehicle="touring"):
    """{name: CarriedInertia}: what the loaded end of each motorcycle component among
    ``components`` (built structures components, e.g. of
    :func:`motoflex_ros.formats.component_file.load_components`) carries in the vehicle file
    ``vehicle`` (a shipped name or a path): the principal hinges' metric in the virtual rig."""
    placed = {c.name: c for c in components if c.name in lumped.CARRIED}
    if not placed:
        return {}
    return carried_by_component(load_vehicle(resolve_config("vehicles", vehicle)), placed)


def _series_hinges(variant, component, identified):
    """[(label, key path of l and beta, key path of k)] of a series variant's hinges."""
    if variant == "decomposed":
        check_split_identifiable(identified, component)
        return [(test, (test,), (key,)) for test, key in (("torsion", "k_t"),
                                                          ("bending", "k_b"))]
    check_principal(identified, component)
    hinges = _need(identified, component, "principal", "hinges", kind=list)
    return [(f"principal{i + 1}", ("principal", "hinges", i), ("principal", "hinges", i, "k"))
            for i in range(len(hinges))]


def _show(value):
    return f"{value:.4g}" if isinstance(value, float) else repr(value)


def _need(identified, component, *keys, kind=float):
    value = identified
    path = ""
    for key in (component, *keys):
        path = f"{path}[{key}]" if isinstance(key, int) else (f"{path}.{key}" if path else key)
        found = (isinstance(value, list) and 0 <= key < len(value) if isinstance(key, int)
                 else isinstance(value, dict) and key in value)
        if not found:
            raise ConfigError(results_source(identified), path, "missing (run motoflex identify "
                                                              "or give a complete result file)")
        value = value[key]
    if kind is list:
        if not isinstance(value, list) or not value:
            raise ConfigError(results_source(identified), path, f"expected a non-empty list, "
                                                              f"got {value!r}")
        return value
    name = keys[-1]
    positive = name.startswith("k")           # stiffness [N m/rad]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise ConfigError(results_source(identified), path, f"expected a finite number, got "
                                                          f"{shown(value)}")
    if (positive and value <= 0) or (name in ("J", "c") and value < 0):
        allowed = "> 0" if positive else ">= 0"
        raise ConfigError(results_source(identified), path,
                          f"value {number_text(value)} is out of the allowed range ({allowed})")
    return float(value)


def flex_joints(variant, component, identified, site, sota=None):
    """The lumped joints (tuple of FlexJoint) of one component in one variant.

    ``identified``: the identification result of all components (the JSON of ``motoflex
    identify``); ``sota``: (point, axis, k) of the state-of-the-art joint, needed only for that
    variant.
    """
    name = f"{component}_{variant}"
    if variant == "rigid":
        return ()
    if variant == "state_of_the_art":
        point, axis, k = sota
        return (FlexJoint(name, np.asarray(point, float), np.asarray(axis, float), k, GAMMA * k),)
    if variant == "static" or variant in HINGE_VARIANTS:
        get = lambda *keys: _need(identified, component, variant, *keys)  # noqa: E731
        point, axis = axis_in_vehicle(site, get("l"), get("beta"))
        return (FlexJoint(name, point, axis, get("k"), GAMMA * get("k")),)
    if variant in ("torsion", "bending"):
        get = lambda *keys: _need(identified, component, variant, *keys)  # noqa: E731
        point, axis = axis_in_vehicle(site, get("l"), get("beta"))
        return (FlexJoint(name, point, axis, get("k"), get("c"), get("J")),)
    if variant in SERIES_VARIANTS:
        joints = []
        for label, where, k_path in _series_hinges(variant, component, identified):
            point, axis = axis_in_vehicle(site, _need(identified, component, *where, "l"),
                                          _need(identified, component, *where, "beta"))
            k = _need(identified, component, *k_path)
            joints.append(FlexJoint(f"{component}_{label}", point, axis, k, GAMMA * k))
        return tuple(joints)
    raise ConfigError("--flex", "variant", f"'{variant}' is not one of: "
                                           f"{', '.join(VARIANTS + HINGE_VARIANTS)}")


def _steer_axis(vehicle):
    role = vehicle.roles.get("steer", "steer")
    return next(j.axis for j in vehicle.joints if j.name == role)


def build_variant(vehicle, variant, names, identified, components):
    """VehicleModel of ``variant`` with the lumped flexibility of the components ``names``."""
    if variant not in FLEX_CHOICES + HINGE_VARIANTS:
        raise ConfigError("--flex", "variant", f"'{variant}' is not one of: "
                                               f"{', '.join(FLEX_CHOICES + HINGE_VARIANTS)}")
    if variant == "rigid":
        return vehicle
    if variant in FLEXIBLE:
        for name in names:
            lumped.check_site(vehicle, name, lumped.site_of(components[name]))
        if variant == "flexible_bodies":
            return per_body_vehicle(vehicle, components, list(names))
        return flexible_vehicle(vehicle, {
            name: superelement_of(components[name], lumped.SUPERELEMENT_PARENT[name],
                                  follows=lumped.SUPERELEMENT_FOLLOWS.get(name))
            for name in names})
    joints = {}
    for name in names:
        site = lumped.site_of(components[name])
        lumped.check_site(vehicle, name, site)
        sota = None
        if variant == "state_of_the_art":
            point, axis = lumped.state_of_the_art_axis(name, site, _steer_axis(vehicle))
            reduced = components[name].clamped_reduced()
            k = state_of_the_art_stiffness(reduced, axis, point - site.origin,
                                                  SOTA_LOAD[name])
            sota = (point, axis, k)
        joints[name] = flex_joints(variant, name, identified, site, sota)
    return lumped.lumped_vehicle(vehicle, variant, joints)


def identified_motorcycle(vehicle="touring", identified=None, components=None):
    """(VehicleModel, description): the lumped 'static' variant of all components identified in
    ``identified`` (identify-format dict) when it can be built, else the rigid ``vehicle``
    (a shipped name or a YAML file). ``components``: {name: structures Component} of (at least)
    the motorcycle components identified."""
    rigid = load_vehicle(resolve_config("vehicles", vehicle))
    names = [n for n in lumped.COMPONENTS if n in (identified or {})]
    if not names:
        return rigid, f"{vehicle} (rigid)"
    try:
        model = build_variant(rigid, "static", names, identified, components or {})
    except (MotoflexError, KeyError, ValueError) as exc:
        return rigid, f"{vehicle} (rigid; lumped 'static' variant not built: {exc})"
    return model, f"{vehicle}, lumped 'static' variant of {', '.join(names)}"
