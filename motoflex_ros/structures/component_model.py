"""The component model every kind shares, and the beam components (config/components/*.yaml).

:class:`ComponentModel` is the chain from a structure to its Craig-Bampton and clamped reduced
models; :class:`Component` is a beam structure. Two YAML formats build one (read by
:mod:`motoflex_ros.formats.component_file`):

- ``component: tube``: the generic validation tube (keys ``tube``, ``material``, ``elements``);
  it starts at the clamp O, lies in the x-z plane at ``pitch_deg`` above x, and its free end is
  the loaded end q0.
- any other ``component`` name: a beam structure (frame, front_assembly, swingarm) with named
  nodes in the component frame (origin O at the clamp point named in the file, axes parallel to
  the vehicle's), members, sections, materials, rigid links, springs, rigid parts and the
  interface nodes (clamps, loaded end). ``placement.origin`` is O in the vehicle frame [m].
"""
import math
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.structures.assembly import AssembledStructure, Structure
from motoflex_ros.structures.beam import tube_section
from motoflex_ros.structures.clamped import (
    check_one_ratio_per_eigenspace,
    clamped_frequencies,
    reduce_clamped,
)
from motoflex_ros.structures.craig_bampton import F_MAX_HZ, N_MODES, craig_bampton
from motoflex_ros.structures.reduction_cache import load_reduction, reduction_key, store_reduction

__all__ = ["ComponentModel", "Component", "tube_component", "DEFAULT_DAMPING_RATIO"]

DEFAULT_DAMPING_RATIO = 0.01  # issue 3: modal damping ratio per mode, default 1 %


class ComponentModel:
    """The chain every kind of component shares: Craig-Bampton, the clamped reduced model for
    the bench, the interface points for the vehicle.

    A kind (:class:`Component` of beams, :class:`~motoflex_ros.structures.mesh_component.
    MeshComponent` of a solid mesh) has the attributes ``name``, ``clamp_nodes``,
    ``loaded_end``, ``interface_nodes`` (clamps first, then the loaded end, then others; each
    with six DOFs ux..rz in the assembled model), ``node_names`` (name -> node index),
    ``origin`` (O in the vehicle frame [m]), ``source`` (its file) and ``damping_ratio``, and
    implements :attr:`node_xyz`, :attr:`elements` and :meth:`assembled`; everything else comes
    from here.
    """

    kind = "component"
    singular_hint = "check the structure and its clamps"

    @property
    def node_xyz(self):
        """Node coordinates in the component frame, (n_nodes, 3) [m]."""
        raise NotImplementedError

    @property
    def elements(self):
        """Node pairs (n, 2) that draw the component (beam elements, a mesh's surface edges)."""
        raise NotImplementedError

    def assembled(self):
        """Sparse K, M of the unclamped model (an AssembledStructure: K, M over its free DOFs,
        ``expand`` to six DOFs per node, ``node_dofs``)."""
        raise NotImplementedError

    def clamped_assembled(self):
        """The assembled model with the clamp nodes' DOFs removed (an AssembledStructure)."""
        asm = self.assembled()
        drop = np.concatenate([asm.node_dofs(n) for n in self.clamp_nodes])
        keep = np.setdiff1d(np.arange(asm.K.shape[0]), drop)
        index = -np.ones(asm.K.shape[0], int)
        index[keep] = np.arange(len(keep))
        free = asm.free_index.copy()
        free[free >= 0] = index[free[free >= 0]]
        return AssembledStructure(K=asm.K[keep][:, keep].tocsc(), M=asm.M[keep][:, keep].tocsc(),
                                  expand=asm.expand[:, keep].tocsr(), free_index=free)

    @property
    def clamp_xyz(self):
        """Clamp node positions in the component frame, (n_clamps, 3) [m]."""
        return self.node_xyz[list(self.clamp_nodes)]

    @property
    def q0(self):
        """Loaded end q0 in the component frame [m]."""
        return self.node_xyz[self.loaded_end]

    def interface_points(self):
        """Named interface points in the vehicle frame [m] (origin + component-frame xyz)."""
        by_index = {i: n for n, i in self.node_names.items()}
        return {by_index.get(i, f"node{i}"): self.origin + self.node_xyz[i]
                for i in self.interface_nodes}

    def craig_bampton(self, n_modes=N_MODES, f_max_hz=F_MAX_HZ, zeta=None):
        """Craig-Bampton model with all DOFs of all interface nodes as boundary.

        ``zeta`` [-] (None: the component's ``damping_ratio``) as in :meth:`clamped_reduced`.
        Returns (CraigBamptonModel, AssembledStructure).
        """
        asm = self.assembled()
        boundary = np.concatenate([asm.node_dofs(n) for n in self.interface_nodes])
        zeta = self.damping_ratio if zeta is None else zeta
        inputs = self.reduction_inputs()
        key = reduction_key(inputs, n_modes, f_max_hz) if inputs else None
        cb = load_reduction(key, zeta) if key else None
        if cb is None or not np.array_equal(cb.boundary, boundary):
            try:
                cb = craig_bampton(asm.K, asm.M, boundary, n_modes, f_max_hz, zeta)
            except ModelError as exc:   # e.g. a singular interior stiffness: name the file
                raise ModelError(f"{self.source or self.name}: {exc} ({self.singular_hint})"
                                 ) from None
            if key:
                store_reduction(key, cb)
        self._check_damping_count(cb)
        return cb, asm

    def reduction_inputs(self):
        """Files whose bytes decide the reduction, for the on-disk cache
        (:mod:`~motoflex_ros.structures.reduction_cache`); () for a model built from a YAML in
        a fraction of a second (no cache)."""
        return ()

    def _check_damping_count(self, cb):
        """ConfigError (file, key damping_ratio) when a per-mode list does not have one value
        per mode of the clamped reduced model, or gives the modes of one degenerate eigenspace
        different values (:func:`check_one_ratio_per_eigenspace`)."""
        keep = self.clamped_coordinates(cb)[0]
        n = len(keep)
        if np.ndim(cb.zeta) and len(cb.zeta) != n:
            raise ConfigError(self.source or self.name, "damping_ratio",
                              f"{len(cb.zeta)} values given; the clamped reduced model has "
                              f"{n} modes ({n - cb.n_modes} free interface DOFs + "
                              f"{cb.n_modes} fixed-interface modes): give one value or {n}")
        if np.ndim(cb.zeta):
            sub = np.ix_(keep, keep)
            try:
                check_one_ratio_per_eigenspace(cb.zeta, clamped_frequencies(cb.M[sub],
                                                                            cb.K[sub]))
            except ModelError as exc:
                raise ConfigError(self.source or self.name, "damping_ratio", str(exc)) from None

    def clamped_reduced(self, n_modes=N_MODES, f_max_hz=F_MAX_HZ, zeta=None):
        """Clamped reduced model (clamp-node DOFs removed) for the bench: ReducedComponent.

        ``zeta`` [-] is the damping ratio of the clamped reduced model's modes: one for all or
        one per mode in ascending frequency (None: the component's ``damping_ratio``).
        """
        cb, asm = self.craig_bampton(n_modes, f_max_hz, zeta)
        keep, end_dofs = self.clamped_coordinates(cb)
        return reduce_clamped(self.name, cb, keep, end_dofs, self.q0, asm.expand)

    def clamped_coordinates(self, cb):
        """Coordinates of :meth:`craig_bampton`'s model ``cb`` left when the clamps are fixed.

        Returns (keep, end_dofs): the indices kept (the clamp nodes' boundary DOFs come first
        and are dropped), and the loaded end's six DOFs (ux..rz) among the kept coordinates.
        """
        n_clamp = 6 * len(self.clamp_nodes)
        keep = np.arange(n_clamp, cb.K.shape[0])
        end_pos = 6 * list(self.interface_nodes).index(self.loaded_end) - n_clamp
        return keep, end_pos + np.arange(6)

    def dof_count(self):
        """Number of DOFs of the full (unclamped, links eliminated) model."""
        return int(self.assembled().K.shape[0])


@dataclass(frozen=True)
class Component(ComponentModel):
    """A clamped beam component: its structure (unclamped; clamps are interface nodes) and names.

    ``node_xyz`` (n, 3) [m] in the component frame; ``elements`` (n_e, 2) node pairs;
    ``clamp_nodes``, ``loaded_end`` node indices; ``interface_nodes`` all boundary nodes
    (clamps first, then the loaded end, then others); ``node_names`` name -> index of the
    named nodes; ``origin`` O in the vehicle frame [m]; ``damping_ratio`` [-] the modal
    damping of the clamped reduced model: one ratio for all modes or one per mode (ascending
    frequency), from the file's optional ``damping_ratio`` key (default 0.01);
    ``body_names`` {name: node index} names flexible bodies (the optional ``bodies`` key;
    :mod:`motoflex_ros.structures.bodies`).
    """

    name: str
    structure: Structure
    clamp_nodes: tuple
    loaded_end: int
    interface_nodes: tuple
    node_names: dict
    origin: np.ndarray
    source: str = ""
    damping_ratio: object = DEFAULT_DAMPING_RATIO
    body_names: dict = None

    kind = "beam"
    singular_hint = "check members, springs, rigid_links and interfaces.clamps"

    @property
    def node_xyz(self):
        """Node coordinates in the component frame, (n_nodes, 3) [m]."""
        return self.structure.xyz

    @property
    def elements(self):
        """Element connectivity, (n_elements, 2) node indices."""
        return np.array([(e[0], e[1]) for e in self.structure.elements], int)

    def assembled(self):
        """Sparse K, M of the unclamped structure (links eliminated)."""
        return self.structure.assemble()

    def clamped_assembled(self):
        """The structure assembled with its clamp nodes fixed."""
        structure = self.structure
        saved = set(structure.clamped)
        structure.clamped.update(self.clamp_nodes)
        try:
            return structure.assemble()
        finally:
            structure.clamped = saved


def tube_component(length, outer_diameter, wall_thickness, pitch_deg, material, elements,
                   name="tube"):
    """Clamped-free tube: O at the clamp, in the x-z plane at pitch_deg above x [m, deg]."""
    pitch = math.radians(pitch_deg)
    direction = np.array([math.cos(pitch), 0.0, math.sin(pitch)])
    s = Structure()
    root = s.add_node([0.0, 0.0, 0.0])
    tip = s.add_node(length * direction)
    up = [0.0, 1.0, 0.0]
    s.add_member(root, tip, int(elements), tube_section(outer_diameter, wall_thickness),
                 material, up=up)
    return Component(name=name, structure=s, clamp_nodes=(root,), loaded_end=tip,
                     interface_nodes=(root, tip), node_names={"clamp": root, "free_end": tip},
                     origin=np.zeros(3))
