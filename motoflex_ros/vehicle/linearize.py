"""Linearization about upright straight running and the speed polynomial of E(v), A(v).

The residual R(x', x; v) (dynamics.py) is differentiated by the complex-step method,
df/dx_k = Im f(x + i h e_k)/h, exact to rounding. Written that way the linearized equations are
polynomial in the forward speed v of degree 2 (gyroscopic and tyre terms linear, centripetal
terms quadratic; a Magic Formula relaxation length sigma(v) = K(a + b v + c v^2) enters E
explicitly as a polynomial), so three linearizations give the coefficient matrices exactly and a
fourth speed checks them. A sweep over many speeds then costs one matrix sum per speed.
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from motoflex_ros.errors import ModelError
from motoflex_ros.vehicle.dynamics import (
    build_system,
    constraint_matrix,
    kinematic_state,
    positions,
    residual,
)

__all__ = ["LinearVehicle", "SecondOrderMatrices", "linearize_at", "linearize",
           "is_singular", "SINGULAR_RTOL", "check_determined", "UNDETERMINED_RTOL",
           "mechanism_matrices", "COMPLEX_STEP", "FIT_SPEEDS"]

COMPLEX_STEP = 1e-30
"""The complex step h of every derivative d f / d x = Im f(x + i h) / h (exact to rounding: no
subtraction), here and in the studies that linearize a vehicle part by part."""
SINGULAR_RTOL = 1e-10
"""E is taken as singular when its smallest singular value is below this fraction of its
largest. Massless bodies make E singular; inside a closed loop their rows come out as rounding
noise rather than exact zeros, where an ordinary solve would not fail but return garbage."""


def is_singular(E, rtol=SINGULAR_RTOL):
    """True when the matrix E (n, n) (or the first of a stack) is numerically singular.

    Rows and then columns are scaled to unit largest entry first (the states mix units: m,
    rad, N; a flexible motorcycle's E spans ten decades unscaled), then the smallest singular
    value is compared with the largest.
    """
    first = np.asarray(E, float)
    first = first[0] if first.ndim == 3 else first
    rows = np.max(np.abs(first), axis=1)
    if np.any(rows == 0.0):
        return True
    scaled = first / rows[:, None]
    scaled = scaled / np.max(np.abs(scaled), axis=0)[None, :]
    s = np.linalg.svd(scaled, compute_uv=False)
    return bool(s[-1] <= rtol * s[0])
FIT_SPEEDS = (1.0, 2.0, 3.0)
"""Speeds [m/s] at which the pencil is linearized to fit its polynomial in v (degree 2)."""
_CHECK_SPEED = 7.5


@dataclass(frozen=True)
class SecondOrderMatrices:
    """M q'' + v C1 q' + (g K0 + v^2 K2) q = f for a model without tyre states (Meijaard 2007
    form); C0 collects speed-independent damping (joint dampers). Units follow q."""

    M: np.ndarray
    C0: np.ndarray
    C1: np.ndarray
    K0: np.ndarray
    K2: np.ndarray


def linearize_at(system, v):
    """(E, A) of E x' = A x at speed v [m/s] by complex-step differentiation."""
    n = system.n_states
    E, A = np.zeros((n, n)), np.zeros((n, n))
    zero = np.zeros(n, complex)
    # the coordinates depend on the position states only: solve them once for every column
    # that perturbs x' or a speed or tyre state
    # (one Newton step is exact for a perturbation of the reference: dynamics.positions)
    q_ref = positions(system, zero, newton_steps=1)
    G_ref = constraint_matrix(system, q_ref)     # the velocity rows at q_ref, shared
    # the residual is linear in x': every column of E perturbs x' at the reference, which
    # shares one kinematic state (frames, contacts, velocity rows)
    reference = kinematic_state(system, zero, v, q=q_ref, G=G_ref)
    n_pos = len(system.indep_pos)
    for k in range(n):
        step = np.zeros(n, complex)
        step[k] = 1j * COMPLEX_STEP
        E[:, k] = residual(system, step, zero, v, at=reference).imag / COMPLEX_STEP
        if k < n_pos:
            A[:, k] = -residual(system, zero, step, v,
                                q=positions(system, step, newton_steps=1)).imag / COMPLEX_STEP
        else:
            A[:, k] = -residual(system, zero, step, v, q=q_ref, G=G_ref).imag / COMPLEX_STEP
    check_determined(system, E, A)
    return E, A


UNDETERMINED_RTOL = 1e-12
"""An independent coordinate whose columns in the equations of motion (its position in A,
its speed in E and A) are below this fraction of the largest entry of E and A there is taken
as carrying neither mass, stiffness nor damping."""


def check_determined(system, E, A):
    """ModelError when an independent coordinate of a force element (a bushing's or a
    superelement's, :mod:`motoflex_ros.vehicle.superelement`) appears in no equation of
    motion: neither mass (its speed's column of E), stiffness (its column of A) nor damping
    (its speed's column of A) in the dynamic rows, e.g. a free direction of a massless bushing
    that no loop determines. The pencil would be singular for every eigenvalue; the message
    names the coordinate and the element. Plain joints are not checked (a study may linearize
    a deliberately free chain and constrain it afterwards, :mod:`motoflex_ros.study.
    hinge_pencil`)."""
    owners = {name: bound.element.name for bound in system.elements
              for name in getattr(bound, "names", ())}
    if not owners:
        return
    nq, nu = len(system.indep_pos), len(system.indep_speed)
    rows = slice(nq, nq + nu)
    e_dyn, a_dyn = np.abs(E[rows]), np.abs(A[rows])
    scale_e = max(float(np.max(e_dyn, initial=0.0)), 1e-300)
    scale_a = max(float(np.max(a_dyn, initial=0.0)), 1e-300)
    speeds = {k: nq + i for i, k in enumerate(system.indep_speed)}
    for j, k in enumerate(system.indep_pos):
        name = system.tree.coordinates[k].name
        if name not in owners or k not in speeds:
            continue
        s = speeds[k]
        mass = np.max(e_dyn[:, s]) / scale_e
        rest = max(np.max(a_dyn[:, j]), np.max(a_dyn[:, s])) / scale_a
        if mass <= UNDETERMINED_RTOL and rest <= UNDETERMINED_RTOL:
            raise ModelError(f"{system.model.source}: coordinate '{name}' of force element "
                             f"'{owners[name]}' has neither mass nor stiffness nor damping and "
                             "no loop determines it (a free direction of a massless element): "
                             "give it stiffness, close it by a joint, or hang a body from it")


def _fit(values, speeds):
    vander = np.vander(np.asarray(speeds), len(speeds), increasing=True)
    stacked = np.array(values).reshape(len(speeds), -1)
    coeffs = np.linalg.solve(vander, stacked)
    return coeffs.reshape((len(speeds),) + values[0].shape)


def _poly(coeffs, speeds):
    speeds = np.atleast_1d(np.asarray(speeds, float))
    powers = speeds[:, None] ** np.arange(len(coeffs))[None, :]
    return np.einsum("sk,kij->sij", powers, coeffs)


@dataclass(frozen=True)
class LinearVehicle:
    """Linearized vehicle: E(v) = sum v^k E_k, A(v) = sum v^k A_k (k = 0, 1, 2)."""

    system: object
    E_coeffs: np.ndarray
    A_coeffs: np.ndarray

    @property
    def state_names(self):
        """Names of the states (coordinates, rates, tyre states)."""
        return self.system.state_names

    def pencil(self, speeds):
        """Stacked E(v), A(v) for the given speeds [m/s], shapes (s, n, n)."""
        return _poly(self.E_coeffs, speeds), _poly(self.A_coeffs, speeds)

    def state_matrix(self, speeds):
        """Stacked A_s(v) = E(v)^-1 A(v) [1/s]; ModelError when E is singular (massless
        bodies: use ``eigenvalues``, which solves the generalized problem)."""
        E, A = self.pencil(speeds)
        if is_singular(E):
            raise ModelError(f"{self.system.model.source}: singular E(v) (massless bodies); "
                             "use the descriptor form")
        return np.linalg.solve(E, A)

    def eigenvalues(self, speed):
        """Finite eigenvalues [1/s] of E x' = A x at one speed (infinite ones dropped)."""
        E, A = self.pencil([speed])
        alpha, beta = scipy.linalg.eig(A[0], E[0], right=False, homogeneous_eigvals=True)
        finite = np.abs(beta) > 1e-12 * np.maximum(np.abs(alpha), 1.0)
        return alpha[finite] / beta[finite]

    def second_order(self):
        """Meijaard-form matrices M, C0, C1, K0, K2 (no tyre states only)."""
        if self.system.n_tyre_states:
            raise ModelError("second-order form exists only without tyre states")
        nq = len(self.system.indep_pos)
        if len(self.system.indep_speed) != nq:
            raise ModelError("second-order form needs one speed per coordinate")
        rows = slice(nq, 2 * nq)
        M = self.E_coeffs[0][rows, rows]
        K = -self.A_coeffs[:, rows, :nq]
        C = -self.A_coeffs[:, rows, nq:]
        return SecondOrderMatrices(M, C[0], C[1], K[0] / self.system.model.gravity, K[2])


def linearize(model):
    """LinearVehicle of a VehicleModel (or a compiled VehicleSystem).

    Linearizes at three speeds, fits the quadratic speed polynomial and checks it at a fourth
    speed; a mismatch (speed dependence the engine does not know about) is a ModelError.
    """
    system = model if hasattr(model, "tree") else build_system(model)
    pencils = [linearize_at(system, v) for v in FIT_SPEEDS]
    result = LinearVehicle(system, _fit([p[0] for p in pencils], FIT_SPEEDS),
                           _fit([p[1] for p in pencils], FIT_SPEEDS))
    E_chk, A_chk = linearize_at(system, _CHECK_SPEED)
    E_fit, A_fit = result.pencil([_CHECK_SPEED])
    for name, got, want in (("E", E_fit[0], E_chk), ("A", A_fit[0], A_chk)):
        error = np.max(np.abs(got - want)) / max(np.max(np.abs(want)), 1.0)
        if error > 1e-9:
            raise ModelError(f"{system.model.source}: {name}(v) is not quadratic in speed "
                             f"(relative error {error:.2e} at {_CHECK_SPEED} m/s)")
    return result


def mechanism_matrices(system, v=0.0):
    """(M, C, K) of M q'' + C q' + K q = f over the independent coordinates of a system with
    one speed per coordinate and no tyre states (a mechanism on a stand, base 'fixed'), from
    :func:`linearize_at` at speed v [m/s]: M [kg..], C [N s/m..], K [N/m..] in the units of
    the coordinates. ModelError otherwise."""
    nq = len(system.indep_pos)
    if system.n_tyre_states or list(system.indep_speed) != list(system.indep_pos):
        raise ModelError(f"{system.model.source}: M, C, K need one speed per coordinate and "
                         "no tyre states (a fixed-base mechanism)")
    E, A = linearize_at(system, v)
    rows = slice(nq, 2 * nq)
    return E[rows, nq:], -A[rows, nq:], -A[rows, :nq]
