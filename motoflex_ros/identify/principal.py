"""Principal hinges: lumped hinges in series from the whole out-of-plane end compliance.

Beyond the paper. The static test (eqs. 1-8) reads one column of the component's end
compliance: the loaded end's out-of-plane motion d = (u_y, theta_x, theta_z) [m, rad] under
F_y at q0. Two more quasi-static tests, moments at q0 about the component's own axes (along
the unit vector e0 of O-q0 and along its normal n in the x-z plane), give the other two columns,
so the whole 3 x 3 compliance C, d = C p with p = (F_y, M_x, M_z) [N, N m], read from the mean
pose of each hold as eqs. 1-8 read it:

    C = D A^-1 W^T,   symmetrised (C + C^T) / 2 (Maxwell-Betti reciprocity),

D the measured (u_y, theta_x, theta_z) columns, A the load amplitudes [N, N m, N m] and W the
orthonormal unit loads (e_y; e0; n) in (F_y, M_x, M_z).

A hinge (revolute spring, axis a = (cos phi, 0, sin phi) in the x-z plane through the joint
P, stiffness k) turns the loaded end by theta = a . (M + (q0 - P) x F) / k, so its compliance
in these coordinates is rank one,

    C_h = v v^T / k,   v = (b, cos phi, sin phi),

b = (a x (q0 - P))_y = (L - l) sin(beta), the arm of eq. (7), beta = phi - atan2(z_q0, x_q0)
(eq. 6), l the joint's distance from O along O-q0 (eq. 5). Hinges in series add their
compliances.

Which hinges: the metric. The carried inertia (what hangs from the loaded end: front
assembly: lower fork and front wheel; swingarm: rear wheel) has the mass matrix G (3 x 3) in
the same coordinates, d' -> kinetic energy d'^T G d' / 2. The loaded end with that inertia on
the end stiffness K = C^-1 has the modes K phi = omega^2 G phi; with phi_i^T G phi_j =
delta_ij,

    C = sum_i phi_i phi_i^T / omega_i^2,

each term a rank-one hinge compliance v v^T / k. The hinges are therefore the principal
directions of C in the metric G: the eigenvectors u_i of S = G^1/2 C G^1/2 with eigenvalues
lambda_i = 1 / omega_i^2 [s^2] (the "singular values" reported, largest first), and

    C_i = C G^1/2 u_i u_i^T G^1/2 C / lambda_i,

which equals phi_i phi_i^T / omega_i^2 when G is invertible and stays defined when it is not.
It is the principled choice because it is the decomposition in which the carried inertia
sees the hinges independently: dropping hinge i (making it rigid) removes exactly the mode
omega_i of the carried body on the end compliance and leaves the others unchanged, so the
hinges kept are the ones that set the low-frequency dynamics of what the component carries
(weave and wobble are far below every omega_i of the shipped components). A metric that does
not pass moments (the frame: the Telelever's spherical head joint passes no moment to the
steering head, G = m e_y e_y^T) has one direction, C_1 = C e_y e_y^T C / C_yy: the static
test's hinge exactly (the axis through the deflection under F_y, k = F b / (b theta)).

Rule for how many hinges to keep: the leading ones up to :data:`MAX_HINGES` (two), and none
whose lambda_i is below :data:`MIN_LAMBDA_SHARE` of lambda_1 (directions the metric does not
see, e.g. the frame's). Two: the carried body's out-of-plane rotation has two components, and
two hinges with independent axes in the x-z plane set its rotation compliance; the third
direction is the stiffest (its omega_3 the highest: front assembly 112 Hz, swingarm 104 Hz on
their carried inertia) and, kept, it makes the chain equal to the 3 x 3 spring K, which the
feasibility study measured worse on the front assembly's wobble (2.3 % e_RMS against 0.7 %
with two): the static compliance is the poorest proxy of the component's dynamic compliance
in its stiffest direction, where the component's own mass (not lumped) matters most. All three
lambda_i are reported so that a user can judge the rule.

Damping c = gamma k with gamma = 0.001 s, as the static models (Sect. 5.2.4).
"""
from dataclasses import dataclass, field

import numpy as np

from motoflex_ros.identify.axis_model import AxisModel
from motoflex_ros.identify.peaks import joint_distance_from_arm, unwrap_axis, wrap_axis
from motoflex_ros.identify.stiffness import static_damping
from motoflex_ros.identify.uncertainty import LEVEL, interval, propagate

__all__ = ["MOMENT_TESTS", "PRINCIPAL_TESTS", "MAX_HINGES", "MIN_LAMBDA_SHARE", "OUT_OF_PLANE",
           "CarriedInertia", "moment_axes", "unit_wrenches", "end_compliance", "hinge_of_vector",
           "principal_compliances", "principal_hinges", "identify_principal",
           "PrincipalIdentification", "hinge_compliance", "not_identified"]

MOMENT_TESTS = ("moment_axial", "moment_normal")
"""The two moment tests: moments at q0 along e0 (O-q0) and along its normal n in x-z."""
PRINCIPAL_TESTS = ("static",) + MOMENT_TESTS
MAX_HINGES = 2
MIN_LAMBDA_SHARE = 1e-9
PSD_TOLERANCE = 1e-9
"""C is a compliance when its smallest eigenvalue is at least -1e-9 of its largest (zero is a
rigid direction, e.g. two hinges only; a negative one beyond round-off is noise)."""
MAX_LOAD_CONDITION = 1e6
"""Largest condition number of the three tests' unit loads (F_y, M_x, M_z) (N and N m mixed:
the shipped tests' is 1)."""
OUT_OF_PLANE = (1, 3, 5)
"""Indices of (u_y, theta_x, theta_z) in a pose (u_x, u_y, u_z, theta_x, theta_y, theta_z)."""


def moment_axes(q0):
    """Unit vectors e0 = (x_q0, 0, z_q0) / L along O-q0 and n = (-e0_z, 0, e0_x), its normal
    in the x-z plane (e0 turned by +90 deg in the sense of eq. 6's angles) [-].

    >>> moment_axes([3.0, 0.0, 4.0])
    (array([0.6, 0. , 0.8]), array([-0.8,  0. ,  0.6]))
    """
    q0 = np.asarray(q0, float)
    e0 = np.array([q0[0], 0.0, q0[2]]) / np.hypot(q0[0], q0[2])
    return e0, np.array([-e0[2], 0.0, e0[0]])


def unit_wrenches(q0):
    """{test: unit wrench (F_x, F_y, F_z, M_x, M_y, M_z) at q0} of the three tests [N/N,
    N m/(N m)]: static F_y; moment_axial along e0; moment_normal along n."""
    e0, n = moment_axes(q0)
    return {"static": np.array([0.0, 1.0, 0.0, 0.0, 0.0, 0.0]),
            "moment_axial": np.r_[np.zeros(3), e0], "moment_normal": np.r_[np.zeros(3), n]}


@dataclass(frozen=True)
class CarriedInertia:
    """What hangs from the loaded end: mass [kg], centre of mass ``com`` [m] (component frame),
    inertia tensor about it [kg m^2]; ``passes_moment`` False when the end passes no moment to
    it (a spherical joint at q0: only the mass at q0 counts, G = m e_y e_y^T); ``source`` where
    it came from (the vehicle file and its bodies, or a bench file's key)."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray
    passes_moment: bool = True
    source: str = ""

    def metric(self, q0):
        """G (3 x 3) [kg, kg m, kg m^2]: kinetic energy d'^T G d' / 2 of the carried rigid body
        moving with the loaded end, d = (u_y, theta_x, theta_z).

        G = J^T diag(m 1, I_c) J with J the velocity of the centre of mass and the angular
        velocity per d': v_c = e_y u_y' - r x omega, omega = (theta_x', 0, theta_z'),
        r = com - q0.

        >>> CarriedInertia(2.0, np.array([0.0, 0.0, -1.0]), np.zeros((3, 3))).metric(
        ...     [0.0, 0.0, 0.0]).round(12).tolist()
        [[2.0, 2.0, 0.0], [2.0, 2.0, 0.0], [0.0, 0.0, 0.0]]
        """
        if not self.passes_moment:
            return np.diag([float(self.mass), 0.0, 0.0])
        r = np.asarray(self.com, float) - np.asarray(q0, float)
        jac = np.zeros((6, 3))
        jac[1, 0] = 1.0
        jac[:3, 1] = -np.cross(r, [1.0, 0.0, 0.0])
        jac[:3, 2] = -np.cross(r, [0.0, 0.0, 1.0])
        jac[3, 1] = jac[5, 2] = 1.0
        mass = np.zeros((6, 6))
        mass[:3, :3] = self.mass * np.eye(3)
        mass[3:, 3:] = np.asarray(self.inertia, float)
        return jac.T @ mass @ jac

    def bench_key(self):
        """The bench file's ``carried`` mapping of this inertia
        (:mod:`motoflex_ros.formats.bench_file`)."""
        i = np.asarray(self.inertia, float)
        return {"mass_kg": float(self.mass), "com_m": [float(v) for v in self.com],
                "inertia_kg_m2": {"xx": float(i[0, 0]), "yy": float(i[1, 1]),
                                  "zz": float(i[2, 2]), "xy": float(i[0, 1]),
                                  "xz": float(i[0, 2]), "yz": float(i[1, 2])},
                "passes_moment": bool(self.passes_moment)}

    def to_dict(self):
        """Plain values (mass_kg, com_m, inertia_kg_m2, passes_moment, source)."""
        return {"mass_kg": float(self.mass), "com_m": [float(v) for v in self.com],
                "inertia_kg_m2": np.asarray(self.inertia, float).tolist(),
                "passes_moment": bool(self.passes_moment), "source": self.source}


def end_compliance(motions, amplitudes, wrenches):
    """C (3 x 3) [m/N, rad/N, m/(N m), rad/(N m)] from the three tests.

    ``motions`` (3, 3): row j the measured (u_y, theta_x, theta_z) [m, rad] of test j;
    ``amplitudes`` (3,) the loads [N or N m]; ``wrenches`` (3, 6) their unit wrenches at q0.
    C = D A^-1 W^T symmetrised (module docstring).

    >>> c = np.array([[2.0, 1.0, 0.0], [1.0, 3.0, 0.0], [0.0, 0.0, 4.0]])
    >>> w = np.eye(6)[[1, 3, 5]]
    >>> end_compliance((c @ np.diag([10.0, 2.0, 1.0])).T, [10.0, 2.0, 1.0], w).tolist()
    [[2.0, 1.0, 0.0], [1.0, 3.0, 0.0], [0.0, 0.0, 4.0]]
    """
    d = np.asarray(motions, float).T / np.asarray(amplitudes, float)
    w = np.asarray(wrenches, float)[:, list(OUT_OF_PLANE)]
    c = d @ np.linalg.inv(w.T)
    return 0.5 * (c + c.T)


def hinge_compliance(k, l, beta, q0):
    """The compliance v v^T / k (3 x 3) of a hinge: k [N m/rad], l [m], beta [rad] (eqs. 5-7),
    v = (b, cos phi, sin phi), phi = atan2(z_q0, x_q0) + beta, b = (L - l) sin(beta).

    Parameters
    ----------
    k : float
        Hinge stiffness [N m/rad].
    l : float
        Joint distance from O along O-q0 [m] (eq. 5).
    beta : float
        Axis angle to O-q0 [rad] (eq. 6).
    q0 : array (3,)
        Loaded end, unloaded [m].

    Returns
    -------
    array (3, 3)
        Compliance in (u_y, theta_x, theta_z) per (F_y, M_x, M_z) [m/N, rad/N, m/(N m),
        rad/(N m)].

    Examples
    --------
    A vertical hinge (beta = 90 deg to O-q0 along x) at 0.4 m with k = 1e4 N m/rad, q0 at 1 m:
    F_y = 1 N turns it by 0.6 / k and moves the end by 0.6^2 / k; M_z = 1 N m turns it by
    1 / k; M_x does nothing:

    >>> c = hinge_compliance(1e4, 0.4, np.pi / 2, [1.0, 0.0, 0.0])
    >>> (np.round(c * 1e4, 12) + 0.0).tolist()
    [[0.36, 0.0, 0.6], [0.0, 0.0, 0.0], [0.6, 0.0, 1.0]]

    """
    theta0 = np.arctan2(q0[2], q0[0])
    b = (np.hypot(q0[0], q0[2]) - l) * np.sin(beta)
    v = np.array([b, np.cos(theta0 + beta), np.sin(theta0 + beta)])
    return np.outer(v, v) / k


def hinge_of_vector(w, q0, reference_beta=None):
    """(l, beta, b, k) of the rank-one compliance w w^T, w = v / sqrt(k) (module docstring).

    k = 1 / (w_2^2 + w_3^2) [N m/rad]; phi = atan2(w_3, w_2); beta = phi - atan2(z_q0, x_q0)
    wrapped into [0, pi) (eq. 6), b = w_1 sqrt(k) following the wrap (eq. 7), l = L - b /
    sin(beta) (eq. 7 solved for l). With ``reference_beta`` beta is unwrapped against it
    instead (for differences across the wrap).
    """
    q0 = np.asarray(q0, float)
    k = 1.0 / (w[1] ** 2 + w[2] ** 2)
    beta = np.arctan2(w[2], w[1]) - np.arctan2(q0[2], q0[0])
    b = w[0] * np.sqrt(k)
    if reference_beta is None:
        beta, b = wrap_axis(beta, b)
    else:
        beta, b = unwrap_axis(beta, b, reference_beta)
    return np.array([joint_distance_from_arm(beta, b, np.hypot(q0[0], q0[2])), beta, b, k])


def _sqrt_psd(g):
    values, vectors = np.linalg.eigh(g)
    return vectors @ np.diag(np.sqrt(np.clip(values, 0.0, None))) @ vectors.T


def principal_compliances(c, g):
    """(lambda (3,) [s^2] largest first, [w_i (3,)]): S = G^1/2 C G^1/2 = sum lambda_i u_i
    u_i^T and each direction's compliance C_i = w_i w_i^T, w_i = C G^1/2 u_i / sqrt(lambda_i)
    (module docstring); w_i is None where lambda_i <= 0."""
    root = _sqrt_psd(np.asarray(g, float))
    lam, u = np.linalg.eigh(root @ np.asarray(c, float) @ root)
    order = np.argsort(lam)[::-1]
    lam, u = lam[order], u[:, order]
    ws = [c @ root @ u[:, i] / np.sqrt(lam[i]) if lam[i] > 0 else None for i in range(3)]
    return lam, ws


def _kept(lam):
    """How many hinges the rule keeps (module docstring)."""
    if not lam[0] > 0:
        return 0
    return int(min(MAX_HINGES, np.sum(lam > MIN_LAMBDA_SHARE * lam[0])))


def principal_hinges(c, g, q0, n_keep=None, references=None):
    """(lambda (3,) [s^2], hinges (n, 4) rows (l, beta, b, k)) of C in the metric G.

    ``n_keep`` None: the rule (:data:`MAX_HINGES`, :data:`MIN_LAMBDA_SHARE`);
    ``references`` the betas to unwrap against (one per hinge).
    """
    lam, ws = principal_compliances(c, g)
    n = _kept(lam) if n_keep is None else n_keep
    refs = references if references is not None else [None] * n
    return lam, np.array([hinge_of_vector(ws[i], q0, refs[i]) for i in range(n)]).reshape(-1, 4)


@dataclass(frozen=True)
class PrincipalIdentification:
    """Principal hinges of one component, or why there are none (``problem``)."""

    identified: bool
    problem: str = None
    hinges: tuple = ()
    lam: tuple = ()
    compliance: np.ndarray = None
    compliance_ci: np.ndarray = None
    metric: np.ndarray = None
    carried: object = None
    info: dict = field(default_factory=dict)

    def to_dict(self):
        """JSON shape: identified, problem, hinges [{l, beta, b, k, c, ci}], lambda_s2 and
        f_hz of all three directions, n_hinges, compliance C and its 95 % half widths, the
        metric and the carried inertia it came from."""
        out = {"identified": self.identified, "problem": self.problem,
               "n_hinges": len(self.hinges), "hinges": [h.to_dict() for h in self.hinges]}
        if self.compliance is not None:   # also on a C refused as indefinite: it is shown
            lam = np.asarray(self.lam, float)
            with np.errstate(divide="ignore", invalid="ignore"):
                f = np.where(lam > 0, 1.0 / (2.0 * np.pi * np.sqrt(np.abs(lam))), np.nan)
            out.update(lambda_s2=[float(v) for v in lam], f_hz=[float(v) for v in f],
                       compliance=self.compliance.tolist(), level=LEVEL, **self.info)
            for key, value in (("compliance_ci_half", self.compliance_ci),
                               ("metric", self.metric)):
                if value is not None:
                    out[key] = value.tolist()
        if self.carried is not None:
            out["carried"] = self.carried.to_dict()
        return out


def not_identified(problem, **kw):
    """A PrincipalIdentification that says why no hinges were identified."""
    return PrincipalIdentification(False, problem, **kw)


def _measured(readings, q0, units):
    """The measured x (9,): (u_y, theta_x, theta_z) of the three tests, its covariance, the
    amplitudes and the unit wrenches."""
    idx = list(OUT_OF_PLANE)
    x = np.concatenate([np.asarray(readings[t].pose, float)[idx] for t in PRINCIPAL_TESTS])
    cov = np.zeros((9, 9))
    for j, t in enumerate(PRINCIPAL_TESTS):
        cov[3 * j:3 * j + 3, 3 * j:3 * j + 3] = np.asarray(readings[t].cov, float)[
            np.ix_(idx, idx)]
    amplitudes = np.array([readings[t].force for t in PRINCIPAL_TESTS], float)
    return x, cov, amplitudes, np.array([units[t] for t in PRINCIPAL_TESTS])


def identify_principal(readings, q0, carried, wrenches=None):
    """PrincipalIdentification from the static and moment readings (by test name) and the
    CarriedInertia (None: not identified, reason given). ``wrenches``: {test: the unit wrench
    (6,) its amplitude multiplies} (default :func:`unit_wrenches`: a measured bench gives the
    loads it measured; any three whose (F_y, M_x, M_z) parts are independent will do).

    Values by the module docstring; 95 % intervals by linear propagation of the three hold
    means' covariances (:mod:`motoflex_ros.identify.uncertainty`). Not identified (with the
    reason, not an error): a moment test missing, no carried inertia, or a C that is
    indefinite (noise larger than the smallest compliance, :data:`PSD_TOLERANCE`) or whose
    kept directions are not positive.
    """
    missing = [t for t in PRINCIPAL_TESTS if t not in readings]
    if missing:
        return not_identified(f"no {' and '.join(missing)} test (a virtual bench: the "
                              "protocol's 'moments' section, moments at q0 along O-q0 and its "
                              "normal; a measured record: two static holds of a moment at q0)")
    if carried is None:
        return not_identified("no carried inertia given (the vehicle file's bodies, or the "
                              "bench file's 'carried' key): the hinges need its metric")
    q0 = np.asarray(q0, float)
    x, cov, amplitudes, wrenches = _measured(readings, q0, {**unit_wrenches(q0),
                                                            **(wrenches or {})})
    out_of_plane = wrenches[:, list(OUT_OF_PLANE)]
    if np.linalg.cond(out_of_plane) > MAX_LOAD_CONDITION:
        return not_identified(f"the three tests' loads (F_y, M_x, M_z) are not independent "
                              f"(condition number {np.linalg.cond(out_of_plane):.3g}): C cannot "
                              "be read from them")
    g = carried.metric(q0)

    def compliance(v):
        return end_compliance(v.reshape(3, 3), amplitudes, wrenches)

    c = compliance(x)
    eig = np.linalg.eigvalsh(c)
    if not eig[0] >= -PSD_TOLERANCE * eig[-1]:
        return not_identified(
            f"the measured end compliance C is indefinite (eigenvalues "
            f"{', '.join(f'{e:.3g}' for e in eig)}): the sensor noise exceeds the deflection of "
            "the stiffest direction; raise the moments' amplitudes (protocol 'moments', or the "
            "real bench's loads) or lower the sensor noise", compliance=c)
    lam, rows = principal_hinges(c, g, q0)
    n = len(rows)
    if n == 0:
        return not_identified("the carried inertia's metric sees no direction of C")
    refs = list(rows[:, 1])

    def outputs(v):
        cc = compliance(v)
        lam_v, hinge_rows = principal_hinges(cc, g, q0, n, refs)
        return np.concatenate([cc[np.triu_indices(3)], lam_v, hinge_rows.ravel()])

    scale = np.maximum(np.abs(x), 1e-12 * np.abs(x).max())
    values, out_cov = propagate(outputs, x, cov, 1e-6 * scale)
    half = np.sqrt(np.clip(np.diag(out_cov), 0.0, None)) * (interval(0.0, 1.0)[1])
    c_half = np.zeros((3, 3))
    c_half[np.triu_indices(3)] = half[:6]
    c_half = c_half + np.triu(c_half, 1).T
    hinges = []
    for i in range(n):
        base = 9 + 4 * i
        vals = dict(zip(("l", "beta", "b", "k"), map(float, rows[i])))
        ci = {name: interval(vals[name], out_cov[base + j, base + j])
              for j, name in enumerate(("l", "beta", "b", "k"))}
        vals["beta"], vals["b"] = wrap_axis(vals["beta"], vals["b"])
        vals["c"] = static_damping(vals["k"])
        ci["c"] = [static_damping(v) for v in ci["k"]]
        if not vals["k"] > 0:
            return not_identified(f"principal hinge {i + 1}: k = {vals['k']:.4g} N m/rad is "
                                  "not positive", compliance=c)
        hinges.append(AxisModel(vals, ci, {"lambda_s2": float(lam[i])}))
    info = {"rule": f"the leading directions up to {MAX_HINGES}, none with lambda below "
                    f"{MIN_LAMBDA_SHARE:g} of the largest",
            "reciprocity": _reciprocity(x, amplitudes, wrenches)}
    return PrincipalIdentification(True, None, tuple(hinges), tuple(map(float, lam)), c,
                                    c_half, g, carried, info)


def _reciprocity(x, amplitudes, wrenches):
    """|C - C^T| / |C| (Frobenius) of the unsymmetrised measured C: Maxwell-Betti says 0; the
    sensor noise and any non-linearity make it larger."""
    d = x.reshape(3, 3).T / amplitudes
    c = d @ np.linalg.inv(np.asarray(wrenches)[:, list(OUT_OF_PLANE)].T)
    return float(np.linalg.norm(c - c.T) / np.linalg.norm(c))
