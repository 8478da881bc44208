"""A component given as a reduced model: the stiffness and mass matrices of a Craig-Bampton (or
any) reduction and its interface nodes.

Read from the engineer's own FE tool's matrices by :mod:`motoflex_ros.formats.superelement_file`
(``component: superelement``; our own reductions are exported in the same form there). It enters
the bench and the vehicle like our own reductions: its matrices are the Craig-Bampton model (no
reduction is made again), the clamps' rows are deleted for the bench. Units SI: K in N/m, N,
N m/rad (1/s^2 on modal rows), M in kg, kg m, kg m^2.
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from motoflex_ros.structures.assembly import AssembledStructure
from motoflex_ros.structures.component_model import DEFAULT_DAMPING_RATIO, ComponentModel
from motoflex_ros.structures.craig_bampton import (
    F_MAX_HZ,
    N_MODES,
    CraigBamptonModel,
    checked_damping_ratio,
)

__all__ = ["SuperelementComponent"]


@dataclass(frozen=True, eq=False)
class SuperelementComponent(ComponentModel):
    """A component given as a reduced model: ``K``, ``M`` (dense, coordinates ordered clamps,
    loaded end, other interface nodes (six each), then the generalized coordinates) and the
    interface nodes' points ``points`` [m] (component frame)."""

    name: str
    K: np.ndarray
    M: np.ndarray
    points: np.ndarray
    clamp_nodes: tuple
    loaded_end: int
    interface_nodes: tuple
    node_names: dict
    origin: np.ndarray
    source: str = ""
    damping_ratio: object = DEFAULT_DAMPING_RATIO

    kind = "superelement"
    singular_hint = "check the superelement's matrices and its interface rows"

    @property
    def node_xyz(self):
        """The interface nodes, (n, 3) [m] in the component frame."""
        return np.asarray(self.points, float)

    @property
    def elements(self):
        """Lines from each clamp to the loaded end (there is no mesh to draw)."""
        return np.array([(c, self.loaded_end) for c in self.clamp_nodes], int)

    def assembled(self):
        """The reduced matrices as the 'full' model; ``expand`` gives the interface nodes' DOFs
        (the generalized coordinates move no node)."""
        n, nb = self.K.shape[0], 6 * len(self.points)
        expand = sp.csr_matrix((np.ones(nb), (np.arange(nb), np.arange(nb))), shape=(nb, n))
        return AssembledStructure(K=sp.csc_matrix(self.K), M=sp.csc_matrix(self.M),
                                  expand=expand, free_index=np.arange(nb))

    def craig_bampton(self, n_modes=N_MODES, f_max_hz=F_MAX_HZ, zeta=None):
        """The superelement's own reduction (``n_modes`` and ``f_max_hz`` do not apply: its
        generalized coordinates are what the FE tool kept). Returns (CraigBamptonModel,
        AssembledStructure)."""
        nb, n = 6 * len(self.points), self.K.shape[0]
        modal = np.arange(nb, n)
        freq = np.sqrt(np.maximum(sla.eigh(self.K[np.ix_(modal, modal)],
                                           self.M[np.ix_(modal, modal)],
                                           eigvals_only=True), 0.0)) / (2 * np.pi) \
            if len(modal) else np.zeros(0)
        zeta = self.damping_ratio if zeta is None else zeta
        cb = CraigBamptonModel(M=self.M, K=self.K, transform=np.eye(n), boundary=np.arange(nb),
                               frequencies_hz=freq, zeta=checked_damping_ratio(zeta))
        self._check_damping_count(cb)
        return cb, self.assembled()
