"""The exact update of the flexible motorcycle's linearized equations when a component changes.

Beyond the paper (issue 26). The flexible motorcycle (``motoflex eig --flex flexible``) carries
each component as a clamped Craig-Bampton superelement (:mod:`motoflex_ros.vehicle.
superelement`): coordinates x (loaded-end DOFs, fixed-interface modes), matrices M, C, K and the
coupling M_xR_P with the rigid motion of each vehicle body P its nodes follow. Its terms of
the equations of motion are

    elastic rows:  M x'' + C x' + K x + sum_P M_xR_P w_P,   w_P = (alpha_P, a_P - R_P^T g)
    all rows:      sum_P J_P^T (M_xR_P^T x'') - J_wP^T ((R_P M_v,P x) x g),

with (alpha_P, a_P) the acceleration field of body P at the origin, J_P = (J_wP; J_vP) its
twist Jacobian, R_P its rotation, g gravity and M_v,P the last three columns of M_xR_P
transposed. Each term is LINEAR in (M, C, K, M_xR_P) at fixed motion. A changed section changes
the component's reduced matrices and nothing else: the rigid bodies, joints, tyres and the
operating point (upright straight running, x = 0) are held. So E(v) and A(v) of E x' = A x
(:mod:`motoflex_ros.vehicle.linearize`) change by

    dE = ROW(dM on x'; sum_P dM_xR_P W^E_P) + COL(sum_P S^T J_P^T dM_xR_P^T on x')
    dA = ROW(-dC on x', -dK on x; sum_P dM_xR_P W^A_P) + COL(sum_P Q_P dM_v,P on x)

where ROW puts a block into the element's dynamic rows and COL into its state columns;
W^E_P, W^A_P (6 x n, quadratic in speed) are the derivatives of w_P by the states, S the
partial velocities (coordinate speeds by independent speeds) and Q_P = -S^T J_wP^T [g]x R_P.
This holds because (i) the element's coordinates are independent, so S's rows for them are
unit rows that do not change with the state, and (ii) at the operating point x'' = x = 0, so
the derivatives of S, J_P and R_P multiply zero in the column terms. W, J, R and S do not
depend on the component, so they are recorded once, while the nominal motorcycle is
linearized (the element's terms are evaluated inside the engine's own residual, by the same
complex-step derivative). A design then costs a re-reduction of the changed components and a
few small matrix products. The number of fixed-interface modes is held at the nominal's (600 Hz
at the nominal), so the state vector keeps its size.

test_design_update.py proves it: the updated E(v), A(v) and their eigenvalues equal a full
re-reduction and linearization of the flexible motorcycle with the changed component files.
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.spatial import cross
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.dynamics import (
    build_system,
    constraint_matrix,
    dependent_speeds,
    positions,
    residual,
)
from motoflex_ros.vehicle.linearize import COMPLEX_STEP, FIT_SPEEDS
from motoflex_ros.vehicle.superelement import BoundSuperelement, coordinate_names, superelement_of
from motoflex_ros.vehicle.variants import flexible_vehicle

__all__ = ["ElementTerms", "DesignEngine", "design_superelement", "design_engine",
           "recorded_linearization"]



def design_superelement(component, n_modes):
    """The component's superelement in the flexible motorcycle, with ``n_modes``
    fixed-interface modes whatever their frequency (so every design has the nominal's size)."""
    name = component.name
    return superelement_of(component, lumped.SUPERELEMENT_PARENT[name], n_modes=n_modes,
                           f_max_hz=np.inf, follows=lumped.SUPERELEMENT_FOLLOWS.get(name))


class _Recorder:
    """A bound superelement that records, at every residual evaluation, the imaginary part of
    w_P (module docstring) of each body P it follows, and J_P, R_P the first time."""

    def __init__(self, bound):
        self.bound = bound
        self.element = bound.element
        self.names = bound.names
        self.calls = []
        self.reference = None

    def generalized_residual(self, system, frames, q, u, udot):
        g = np.array([0.0, 0.0, -system.model.gravity])
        w = []
        for frame in self.bound.frames:
            f = frames[frame]
            alpha = f.Jw @ udot + f.dw
            a0 = f.Jv @ udot + f.dv0 + cross(f.w, f.v0) - f.R.T @ g
            w.append(np.concatenate([alpha, a0]).imag)
        if self.reference is None:
            self.reference = [(np.real(frames[i].Jw), np.real(frames[i].Jv),
                               np.real(frames[i].R)) for i in self.bound.frames]
        self.calls.append(np.array(w))
        return self.bound.generalized_residual(system, frames, q, u, udot)


def _linearize_recording(system, v, recorders):
    """(E, A) at speed v [m/s] by complex step, each column's residual evaluated once with the
    recorders in place (the same evaluations as vehicle.linearize.linearize_at)."""
    n = system.n_states
    E, A = np.zeros((n, n)), np.zeros((n, n))
    zero = np.zeros(n, complex)
    q_ref = positions(system, zero, newton_steps=1)
    G_ref = constraint_matrix(system, q_ref)
    for k in range(n):
        step = np.zeros(n, complex)
        step[k] = 1j * COMPLEX_STEP
        E[:, k] = residual(system, step, zero, v, q=q_ref, G=G_ref).imag / COMPLEX_STEP
        q = positions(system, step, newton_steps=1) if k < len(system.indep_pos) else q_ref
        A[:, k] = -residual(system, zero, step, v, q=q,
                            G=None if k < len(system.indep_pos) else G_ref).imag / COMPLEX_STEP
    calls = {}
    for name, rec in recorders.items():
        got = np.array(rec.calls)                       # (2 n, frames, 6)
        if got.shape[0] != 2 * n:
            raise ModelError(f"superelement '{name}' was evaluated {got.shape[0]} times for "
                             f"{2 * n} columns")
        calls[name] = (np.moveaxis(got[0::2], 0, -1) / COMPLEX_STEP,
                       -np.moveaxis(got[1::2], 0, -1) / COMPLEX_STEP)
        rec.calls.clear()
    return E, A, calls


def _partial_velocities(system):
    """S (coordinates x independent speeds) at the reference: u = S u_indep."""
    n = len(system.tree.coordinates)
    q_ref = np.real(positions(system, np.zeros(system.n_states), newton_steps=1))
    S = np.zeros((n, len(system.indep_speed)))
    for i, k in enumerate(system.indep_speed):
        known = np.zeros(n)
        known[k] = 1.0
        S[:, i] = dependent_speeds(system, q_ref, known)
    return S


def _fit(values):
    """Speed-polynomial coefficients (degree + 1, ...) of values at FIT_SPEEDS."""
    vander = np.vander(np.asarray(FIT_SPEEDS), len(FIT_SPEEDS), increasing=True)
    stacked = np.array(values)
    coeffs = np.linalg.solve(vander, stacked.reshape(len(FIT_SPEEDS), -1))
    return coeffs.reshape(stacked.shape)


@dataclass(frozen=True, eq=False)
class ElementTerms:
    """What a component's superelement does to E(v), A(v) (module docstring).

    element: the nominal Superelement; rows: its dynamic rows (= its rate states' indices);
    pos: its position states' indices; w_E, w_A: (degree + 1, frames, 6, n) speed-polynomial
    coefficients of W^E_P, W^A_P; col_E (frames, n, 6) = S^T J_P^T and col_A (frames, n, 3) =
    Q_P, both in the dynamic rows.
    """

    element: object
    rows: np.ndarray
    pos: np.ndarray
    w_E: np.ndarray
    w_A: np.ndarray
    col_E: np.ndarray
    col_A: np.ndarray

    def delta(self, element):
        """(dE, dA) speed-polynomial coefficients (degree + 1, n, n) of replacing the nominal
        element by ``element`` (same coordinates, same bodies followed)."""
        nominal = self.element
        if element.M.shape != nominal.M.shape or len(element.couplings) != len(self.col_E):
            raise ModelError(f"superelement '{element.name}': {element.M.shape[0]} coordinates "
                             f"and {len(element.couplings)} bodies, the nominal has "
                             f"{nominal.M.shape[0]} and {len(self.col_E)}")
        n = self.col_E.shape[1]
        dE = np.zeros((self.w_E.shape[0], n, n))
        dA = np.zeros_like(dE)
        rows, pos = self.rows, self.pos
        dE[0][np.ix_(rows, rows)] += element.M - nominal.M
        dA[0][np.ix_(rows, rows)] -= element.C - nominal.C
        dA[0][np.ix_(rows, pos)] -= element.K - nominal.K
        for p, ((_, new), (_, old)) in enumerate(zip(element.couplings, nominal.couplings)):
            dx = np.asarray(new) - np.asarray(old)
            dE[:, rows, :] += np.einsum("ij,kjn->kin", dx, self.w_E[:, p])
            dA[:, rows, :] += np.einsum("ij,kjn->kin", dx, self.w_A[:, p])
            dE[0][:, rows] += self.col_E[p] @ dx.T
            dA[0][:, pos] += self.col_A[p] @ dx[:, 3:].T
        return dE, dA


def _terms(system, rec, calls, S):
    names = list(system.state_names)
    element = rec.element
    coords = coordinate_names(element)
    indep = {system.tree.coordinates[k].name for k in system.indep_pos}
    if not set(coords) <= indep:
        raise ModelError(f"superelement '{element.name}': its coordinates must be independent "
                         "for the design update")
    rows = np.array([names.index(f"{c}_rate") for c in coords])
    pos = np.array([names.index(c) for c in coords])
    nq, nu, n = len(system.indep_pos), len(system.indep_speed), system.n_states
    skew_g = np.cross(np.eye(3), np.array([0.0, 0.0, -system.model.gravity]))
    col_E = np.zeros((len(rec.reference), n, 6))
    col_A = np.zeros((len(rec.reference), n, 3))
    for p, (jw, jv, rot) in enumerate(rec.reference):
        col_E[p, nq:nq + nu] = S.T @ np.vstack([jw, jv]).T
        col_A[p, nq:nq + nu] = S.T @ jw.T @ skew_g.T @ rot
    w_E = _fit([c[0] for c in calls])
    w_A = _fit([c[1] for c in calls])
    return ElementTerms(element, rows, pos, w_E, w_A, col_E, col_A)


def recorded_linearization(model, names):
    """(E_coeffs, A_coeffs, {name: ElementTerms}) of the flexible ``model``: its speed
    polynomials (degree 2, as :func:`motoflex_ros.vehicle.linearize.linearize`) and the terms
    of the superelements ``names``, from one pass of complex-step linearizations."""
    system = build_system(model)
    recorders = {b.element.name: _Recorder(b) for b in system.elements
                 if isinstance(b, BoundSuperelement) and b.element.name in names}
    missing = set(names) - set(recorders)
    if missing:
        raise ModelError(f"the motorcycle has no superelement {', '.join(sorted(missing))}")
    bound = tuple(recorders.get(getattr(b, "element", None) and b.element.name, b)
                  for b in system.elements)
    recording = replace(system, elements=bound)
    runs = [_linearize_recording(recording, v, recorders) for v in FIT_SPEEDS]
    S = _partial_velocities(system)
    terms = {name: _terms(system, rec, [r[2][name] for r in runs], S)
             for name, rec in recorders.items()}
    return _fit([r[0] for r in runs]), _fit([r[1] for r in runs]), terms, system


@dataclass(frozen=True, eq=False)
class DesignEngine:
    """The nominal flexible motorcycle's E(v), A(v) and each varied component's terms.

    E_coeffs, A_coeffs: (3, n, n) speed-polynomial coefficients; terms: {component:
    ElementTerms}; n_modes: {component: fixed-interface modes kept}; system: the compiled
    nominal motorcycle (for the modal sweep that names weave and wobble).
    """

    E_coeffs: np.ndarray
    A_coeffs: np.ndarray
    terms: dict
    n_modes: dict
    system: object

    def superelements(self, components):
        """{name: Superelement} of ``components`` ({name: structures Component}, any subset of
        the varied ones), each re-reduced with its nominal number of modes."""
        return {name: design_superelement(c, self.n_modes[name])
                for name, c in components.items()}

    def coefficients(self, superelements):
        """(E_coeffs, A_coeffs) of the motorcycle with ``superelements`` ({name:
        Superelement}, e.g. :meth:`superelements`) in place of the nominal ones."""
        E, A = self.E_coeffs.copy(), self.A_coeffs.copy()
        for name, element in superelements.items():
            dE, dA = self.terms[name].delta(element)
            E += dE
            A += dA
        return E, A


def design_engine(vehicle, components, varied):
    """DesignEngine of the flexible ``vehicle`` (a rigid VehicleModel) with ``components``
    ({name: Component}, the three of the motorcycle) as superelements, ``varied`` the names
    whose sections may change."""
    n_modes = {name: int(components[name].craig_bampton()[0].n_modes) for name in components}
    model = flexible_vehicle(vehicle, {name: design_superelement(c, n_modes[name])
                                       for name, c in components.items()})
    E, A, terms, system = recorded_linearization(model, tuple(varied))
    return DesignEngine(E, A, terms, {n: n_modes[n] for n in varied}, system)
