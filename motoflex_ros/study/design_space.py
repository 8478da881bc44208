"""The design space of ``motoflex study design``: which sections may change, and the constraints.

Beyond the paper (Sect. 1 and 6 state the aim: "optimize the stiffness in the early design
phase of structural components so that the overall weight can be minimized while ensuring the
stability of weave and wobble"; issue 26). A design space file (config/design/*.yaml) names,
per component, the sections of its beam file that may change and the bounds of each dimension
(outer diameter, wall thickness, width, height [m]); everything else is held: geometry (nodes,
members), materials, springs, rigid parts, clamps, the rest of the motorcycle. The constraints
are floors on the four stability indices of eq. (15) (weave and wobble, 40-100 and 100-210
km/h): ``nominal`` (at least the nominal design's) or a number; and optional floors per
component on the static stiffness k about the static deformation axis [N m/rad] (eq. 8) and on
the first eigenfrequency of the clamped model [Hz], a stand-in for strength (a real design
needs stress checks this rig does not make).

The objective is the structural mass: the FE members' mass, density x section area x length,
summed over the members of the three components [kg] (rigid parts held, not counted).

Symbols: D outer diameter, t wall thickness, w width, h height [m]; rho density [kg/m^3].

The design space file is read at the edge (:mod:`motoflex_ros.formats.design_space_file`: it
names the components' beam files, reads them and writes the changed ones); here is the
validated :class:`DesignSpace` the study takes and what it computes of a design.
"""
import copy
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.structures.beam import rectangular_tube_section, tube_section
from motoflex_ros.structures.component_model import Component
from motoflex_ros.structures.component_schema import (
    SECTION_SIZE_M,
    WALL_M,
    damping_ratio_setting,
    structure_from_config,
)

__all__ = ["SECTION_KEYS", "SECTION_RANGES", "DesignSpace", "Variable",
           "members_mass", "component_with", "design_configs"]

"""The four stability indices of eq. (15): mode x speed range (low 40-100, high 100-210 km/h)."""
SECTION_KEYS = {"tube": ("outer_diameter", "wall_thickness"),
                "rectangular_tube": ("width", "height", "wall_thickness")}
"""The dimensions each section shape has (structures/component_schema.py), all in [m]."""
SECTION_RANGES = {"outer_diameter": SECTION_SIZE_M, "width": SECTION_SIZE_M,
                  "height": SECTION_SIZE_M, "wall_thickness": WALL_M}
"""The range [m] each dimension's bounds must lie in: the beam schema's."""

@dataclass(frozen=True)
class Variable:
    """One design variable: ``component``'s section ``section``, dimension ``key`` [m], in
    [low, high], nominal value ``nominal`` [m]; ``name`` 'component.section.key'."""

    component: str
    section: str
    key: str
    low: float
    high: float
    nominal: float

    @property
    def name(self):
        """'component.section.key'."""
        return f"{self.component}.{self.section}.{self.key}"


@dataclass(frozen=True, eq=False)
class DesignSpace:
    """A validated design space.

    source: its file; vehicle: the vehicle name or file; variables: tuple of Variable;
    configs: {component: validated beam config (the nominal design)}; sources: {component:
    its beam file}; index_floors: {index: 'nominal' or a number} (eq. 15); floors: {component:
    {'min_static_k' [N m/rad], 'min_first_frequency_hz' [Hz]}} (strength stand-ins).
    """

    source: str
    vehicle: str
    variables: tuple
    configs: dict
    sources: dict
    index_floors: dict
    floors: dict

    @property
    def names(self):
        """Variable names in order."""
        return tuple(v.name for v in self.variables)

    @property
    def lower(self):
        """Lower bounds (variables,) [m]."""
        return np.array([v.low for v in self.variables])

    @property
    def upper(self):
        """Upper bounds (variables,) [m]."""
        return np.array([v.high for v in self.variables])

    @property
    def nominal(self):
        """Nominal values (variables,) [m]."""
        return np.array([v.nominal for v in self.variables])

    def components(self):
        """Components whose sections may change, in file order."""
        return tuple(dict.fromkeys(v.component for v in self.variables))

    def with_floors(self, index_floors):
        """The same space with other index floors ({index: 'nominal' or number})."""
        return replace(self, index_floors=dict(index_floors))


def design_configs(space, values):
    """{component: beam config} of the design ``values`` (variables,) [m]: copies of the
    nominal configs with the varied dimensions set."""
    out = {}
    for variable, value in zip(space.variables, np.asarray(values, float)):
        cfg = out.setdefault(variable.component, copy.deepcopy(space.configs[variable.component]))
        cfg["sections"][variable.section][variable.key] = float(value)
    return out


def component_with(cfg, source):
    """The beam Component of a (validated, possibly changed) config dict ``cfg`` read from the
    file ``source``."""
    comp = structure_from_config(copy.deepcopy(cfg), source, Component)
    return replace(comp, source=str(source),
                   damping_ratio=damping_ratio_setting(cfg.get("damping_ratio"), source))


def _area(spec):
    if spec["shape"] == "tube":
        return tube_section(spec["outer_diameter"], spec["wall_thickness"]).A
    return rectangular_tube_section(spec["width"], spec["height"], spec["wall_thickness"]).A


def members_mass(cfg):
    """Structural mass of a beam config's members [kg]: sum of rho A L over the members
    (rigid parts not counted).

    Parameters
    ----------
    cfg : dict
        A beam component config (config/components/*.yaml as read): ``nodes`` [m],
        ``materials`` (``rho`` [kg/m^3]), ``sections`` (dimensions [m]) and ``members``.

    Returns
    -------
    float
        The members' mass [kg].

    Examples
    --------
    >>> cfg = {"nodes": {"a": [0, 0, 0], "b": [2.0, 0, 0]},
    ...        "materials": {"steel": {"rho": 7850.0}},
    ...        "sections": {"s": {"shape": "rectangular_tube", "width": 0.02, "height": 0.02,
    ...                           "wall_thickness": 0.001}},
    ...        "members": [{"from": "a", "to": "b", "section": "s", "material": "steel"}]}
    >>> round(members_mass(cfg), 6)   # 7850 kg/m^3 x (0.02^2 - 0.018^2) m^2 x 2 m
    1.1932

    """
    nodes = {k: np.asarray(v, float) for k, v in cfg["nodes"].items()}
    areas = {k: _area(v) for k, v in cfg["sections"].items()}
    return float(sum(cfg["materials"][m["material"]]["rho"] * areas[m["section"]]
                     * np.linalg.norm(nodes[m["to"]] - nodes[m["from"]])
                     for m in cfg["members"]))
