"""A lumped hinge fitted to the flexible motorcycle: the "fitted" variant (beyond the paper).

The paper identifies each component's hinge on the bench; here, for comparison, the single
hinge per component that the motorcycle itself asks for: the axis (in the component's symmetry
plane), its position and the stiffness k (c = gamma k, gamma = 0.001 s, as the static models)
that minimise

    J = sqrt(sum over weave f, weave Re, wobble f, wobble Re of e_RMS%^2)  [%]
        (eq. 18 over the speeds given, the paper's 40-210 km/h)

against the flexible motorcycle's weave and wobble, the rest of the lumped motorcycle being the
static variant's (inertia distribution of Sect. 5.2). The flexible reference is an input (the
curves the accuracy study computes from its flexible motorcycle), so the fit follows that
reference however it is built.

Search: Nelder-Mead (scipy) from the static identification and from the best (as it is) of
any other starts given (the accuracy study gives the road_load and vehicle_load hinges: from
static alone the front assembly's search ends in a local minimum), each on about 12 of the
speeds, with one restart; the best end point is polished on all speeds. The simplex variables
are the hinge's compliance vector at q0 in the antisymmetric motions (u_y, theta_x, theta_z),
v = (b, cos theta, sin theta) / sqrt(k), scaled by the static hinge's (steps of 1 cm, 2 deg
and 10 % of k, in size); theta = theta_0 + beta is the axis direction, b the signed arm of q0
((L - l) sin beta, eq. 7). Every evaluation is cheap: the hinge motorcycle's pencils come from
one linearization for any hinge (:class:`~motoflex_ros.study.hinge_pencil.HingePencil`);
weave and wobble are continued (:mod:`motoflex_ros.study.continuation`) in the hinge from the
nearest hinge evaluated before, all speeds at once, or else over speed from the first speed,
where they start from the static motorcycle's (named by mode shape by the engine).

With several components in ``names`` the hinges are fitted jointly (one simplex over all their
variables); the accuracy study instead fits each on its own case (in turn).

Tie-break: the simplex minimises J + TIE_BREAK |x - x_static| (x the scaled variables, so the
distance is in steps of 2 deg, 1 cm, 10 % of k). Where weave and wobble see the hinge only
through one combination of its parameters (the frame: the steering head's lateral compliance
b^2/k) J alone slides towards b -> 0, k -> 0 (the head sliding sideways without turning, no
hinge; |x| grows as 1/sqrt(k)); the term keeps the fit a hinge and pulls it towards the bench
identification. It does not make a flat valley's answer unique (the frame's search ends at
40 or 124 deg to O-q0 depending on the start, test_study_fitted). Where weave and wobble see
all three parameters it moves the optimum by thousandths of a step (J's curvature is
0.3-5 % per step^2). The J reported is without it.

Besides the fit, the lumped motorcycle with the component's whole end stiffness in the hinge's
place (:meth:`HingePencil.spring_pencil`, K = C^-1 of the clamped FE model, massless) is
evaluated the same way: what any stiffness at that place can reach, against which the single
hinge is judged.

Conditioning of the optimum: e_RMS% with one of k +-10 %, the axis turned +-2 deg about its
point nearest q0 (b kept), or the axis moved +-1 cm normal to itself in the symmetry plane
(b +-1 cm), the rest at the optimum.
"""
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from motoflex_ros.errors import ModelError
from motoflex_ros.identify.results import ResultsFile
from motoflex_ros.study.accuracy import QUANTITIES, rms_error_percent
from motoflex_ros.study.continuation import continue_eigenpairs, mac, nearest_eigenpairs
from motoflex_ros.study.hinge_pencil import HingePencil
from motoflex_ros.study.tracked import HomotopyStart
from motoflex_ros.study.variants import GAMMA
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["Hinge", "HingeFit", "HingeFitProblem", "fit_hinges", "with_fitted", "objective_of",
           "hinge_of", "hinge_line", "hinge_from_line", "static_hinge", "perturbed",
           "PERTURBATIONS", "STEPS", "TIE_BREAK", "end_compliance",
           "hinge_compliance", "fit_under_compliance"]

STEPS = {"beta": math.radians(2.0), "b": 0.01, "log_k": 0.1}
"""Scales of the simplex variables: 2 deg, 1 cm, 10 % of k (``space`` 'line': beta, b, ln k;
'compliance': the compliance vector, module docstring)."""
PERTURBATIONS = (("k -10%", "k", 0.9), ("k +10%", "k", 1.1),
                 ("axis -2 deg", "beta", -math.radians(2.0)),
                 ("axis +2 deg", "beta", math.radians(2.0)),
                 ("position -1 cm", "b", -0.01), ("position +1 cm", "b", 0.01))
"""Conditioning: (label, parameter, change): k scaled, beta or b shifted [rad, m]."""
TIE_BREAK = 1e-3
"""Weight [% per scaled step] of the distance from the static hinge in the simplex's objective
(module docstring): small against J's curvature, and any positive weight keeps a flat valley's
search away from k -> 0."""
_FAILED = 1e12
"""Objective of a hinge whose modes cannot be followed (continuation failed)."""


@dataclass(frozen=True)
class Hinge:
    """A hinge in the component frame as the paper gives it (eqs. 5-8): l [m] along O-q0, beta
    [rad] to O-q0, b [m] = (L - l) sin beta, k [N m/rad], c [N m s/rad] = gamma k."""

    l: float
    beta: float
    b: float
    k: float

    @property
    def c(self):
        """Damping [N m s/rad] of the static models, gamma k."""
        return GAMMA * self.k

    def to_dict(self):
        """{"l", "beta", "b", "k", "c"} (the keys of an identified static model)."""
        return {"l": self.l, "beta": self.beta, "b": self.b, "k": self.k, "c": self.c}


def _plane(site):
    q0 = np.asarray(site.q0, float)
    return math.hypot(q0[0], q0[2]), math.atan2(q0[2], q0[0])


def hinge_from_line(site, beta, b, k):
    """Hinge with axis angle ``beta`` [rad] and signed arm ``b`` [m] of q0 (l = L - b/sin beta)."""
    length, _ = _plane(site)
    turns = math.floor(beta / math.pi)       # the same line with the axis reversed: b flips
    beta, b = beta - turns * math.pi, b * (-1.0) ** turns
    s = math.sin(beta)
    if abs(s) < 1e-9:
        raise ModelError(f"component '{site.name}': a hinge parallel to O-q0 has no l")
    return Hinge(length - b / s, float(beta), float(b), float(k))


def hinge_line(site, hinge):
    """(point [m], unit axis) in the vehicle frame: the axis's point nearest q0, q0 + b n."""
    _, theta0 = _plane(site)
    angle = theta0 + hinge.beta
    axis = np.array([math.cos(angle), 0.0, math.sin(angle)])
    normal = np.array([-math.sin(angle), 0.0, math.cos(angle)])
    return site.origin + site.q0 + hinge.b * normal, axis


def hinge_compliance(site, hinge, wrench):
    """The hinge's compliance w . C_h . w [m/N] under the wrench w = ``wrench`` (F [N], M [N m]
    at q0, vehicle axes): C_h = s s^T / k, s = (a x (q0 - p), a) its unit twist at q0."""
    point, axis = hinge_line(site, hinge)
    twist = np.concatenate([np.cross(axis, site.origin + site.q0 - point), axis])
    return float(twist @ np.asarray(wrench, float)) ** 2 / hinge.k


def perturbed(site, hinge, what, change):
    """The hinge with k scaled by ``change`` (what "k"), or beta or b shifted by it [rad, m]
    (the axis turned about its point nearest q0, or moved normal to itself)."""
    if what == "k":
        return Hinge(hinge.l, hinge.beta, hinge.b, hinge.k * change)
    if what == "beta":
        return hinge_from_line(site, hinge.beta + change, hinge.b, hinge.k)
    if what == "b":
        return hinge_from_line(site, hinge.beta, hinge.b + change, hinge.k)
    raise ValueError(f"unknown hinge parameter '{what}'")


def hinge_of(values):
    """Hinge from a model's values {"l", "beta", "b", "k", ...} (an identified static model)."""
    return Hinge(float(values["l"]), float(values["beta"]), float(values["b"]),
                 float(values["k"]))


def static_hinge(identified, component, site):
    """The identified static hinge (l, beta, k; b from eq. 7 on the component's q0)."""
    static = identified[component]["static"]
    length, _ = _plane(site)
    beta = float(static["beta"])
    return Hinge(float(static["l"]), beta, (length - float(static["l"])) * math.sin(beta),
                 float(static["k"]))


@dataclass(frozen=True, eq=False)
class HingeFit:
    """Result of a hinge fit.

    names: the components; hinges, static: {component: Hinge}; errors, static_errors: {quantity:
    e_RMS%} of the fitted and the static hinges (same evaluation); objective: J [%^2];
    conditioning: {component: {label: {quantity: e_RMS%}}}; evaluations: objective calls;
    seconds: wall time; how: "single", or "jointly" for several components; start: the label
    of the start the result came from; starts: {label: {"objective": J on the search speeds,
    "hinges": where the search from it ended}}; spring_errors: {quantity: e_RMS%} of the
    motorcycle with the components' whole FE end stiffness in the hinges' place (None where
    its weave or wobble could not be followed).
    """

    names: tuple
    hinges: dict
    static: dict
    errors: dict
    static_errors: dict
    objective: float
    conditioning: dict
    evaluations: int
    seconds: float
    how: str
    speeds: np.ndarray = field(default=None, repr=False)
    start: str = "static"
    starts: dict = field(default_factory=dict)
    spring_errors: dict = None

    def identified(self, identified):
        """A copy of the identification results with a "fitted" model in each fitted
        component (the keys of a static one), for :func:`build_variant` 'fitted'."""
        return with_fitted(identified, [self])

    def to_dict(self):
        """Plain dict (JSON): per component the fitted and static hinges and the conditioning."""
        return {"how": self.how, "objective": self.objective, "evaluations": self.evaluations,
                "seconds": self.seconds, "start": self.start, "starts": self.starts,
                "errors": dict(self.errors),
                "static_errors": dict(self.static_errors),
                "end_stiffness_errors": (dict(self.spring_errors) if self.spring_errors
                                         else None),
                "components": {name: {"fitted": self.hinges[name].to_dict(),
                                      "static": self.static[name].to_dict(),
                                      "conditioning": self.conditioning[name]}
                               for name in self.names}}


def with_fitted(identified, fits):
    """A copy of the identification results with the "fitted" hinges of all ``fits``."""
    out = {name: dict(result) for name, result in identified.items()}
    if isinstance(identified, ResultsFile):
        out = ResultsFile(out, identified.source)
    for fit in fits:
        for name, hinge in fit.hinges.items():
            out[name]["fitted"] = hinge.to_dict()
    return out


def _errors(lumped_curves, reference):
    out = {}
    for mode in ("weave", "wobble"):
        lu, fl = lumped_curves[mode], reference[mode][None, :]
        out[f"{mode}_f"] = rms_error_percent(lu.imag / (2 * np.pi),
                                             np.broadcast_to(fl.imag / (2 * np.pi), lu.shape))
        out[f"{mode}_re"] = rms_error_percent(lu.real, np.broadcast_to(fl.real, lu.shape))
    return out


def end_compliance(component):
    """C (6, 6): the clamped FE model's loaded-end motion (u [m], theta [rad]) per unit wrench
    (F [N], M [N m]) at q0 (the bench's reduced model; symmetrized, vehicle axes)."""
    reduced = component.clamped_reduced()
    c = np.column_stack([reduced.static_end_motion(e) for e in np.eye(6)])
    return 0.5 * (c + c.T)


class HingeFitProblem:
    """The hinge fit's evaluations: hinges -> weave and wobble over speed -> e_RMS%.

    Parameters
    ----------
    vehicle, components, identified : as :func:`motoflex_ros.study.variants.build_variant`
    names : sequence of str
        The components with a fitted hinge (the others rigid, as in the accuracy study).
    reference : mapping
        {"weave": complex (speeds,), "wobble": ...} of the flexible motorcycle [1/s].
    speeds : array
        Speeds [m/s] of ``reference``.

    Weave and wobble of each hinge motorcycle start at the first speed from the eigenpairs
    nearest to the static motorcycle's (named by the engine's modal sweep, by mode shape);
    where the eigenvector's MAC with the static one is below ``START_MAC`` they are continued
    from the static motorcycle instead (homotopy in the matrices), then over speed.

    """

    START_MAC = 0.8
    WARM_RADIUS = 10.0
    WARM_STEPS = 2
    WARM_MAC = 0.95
    CACHE = 8
    space = "compliance"

    def __init__(self, vehicle, components, identified, names, reference, speeds):
        self.names = tuple(names)
        self.speeds = np.asarray(speeds, float)
        self.reference = {m: np.asarray(reference[m], complex) for m in ("weave", "wobble")}
        for mode, curve in self.reference.items():
            if curve.shape != self.speeds.shape or not np.all(np.isfinite(curve)):
                raise ModelError(f"the flexible reference's {mode} must be tracked at every "
                                 f"one of the {len(self.speeds)} speeds")
        self.sites = {n: lumped.site_of(components[n]) for n in self.names}
        self.static = {n: static_hinge(identified, n, self.sites[n]) for n in self.names}
        self.pencil = HingePencil(vehicle, components, identified, self.names)
        sweep = modal_sweep(linearize(self.pencil.base), self.speeds[:1])
        targets = tuple(complex(sweep.modes[m][0]) for m in ("weave", "wobble"))
        if not all(np.isfinite(t) for t in targets):
            raise ModelError(f"the static motorcycle ({', '.join(self.names)}) has no weave or "
                             "wobble at the first speed")
        e0, a0 = self.pencil.pencil([self._vehicle_hinges(self.static)], self.speeds[:1])
        self._homotopy = HomotopyStart(nominal=(e0[0, 0], a0[0, 0]), targets=targets)
        self._static_pairs = nearest_eigenpairs(a0[:, 0], np.asarray(targets),
                                                descriptor=e0[:, 0])
        self.evaluations = 0
        self._grid = np.arange(len(self.speeds))
        self._cache = []

    def on_speeds(self, index):
        """The same problem on the speeds ``self.speeds[index]`` (shares the linearization)."""
        other = object.__new__(HingeFitProblem)
        other.__dict__.update(self.__dict__)
        other._grid = self._grid[index]
        other._cache = []
        return other

    @property
    def grid(self):
        """Speeds [m/s] the errors are evaluated on."""
        return self.speeds[self._grid]

    def _vehicle_hinges(self, hinges):
        out = {}
        for name, hinge in hinges.items():
            point, axis = hinge_line(self.sites[name], hinge)
            out[name] = (point, axis, hinge.k)
        return out

    def _start(self, e0, a0):
        lam, vec = nearest_eigenpairs(a0, self._static_pairs[0][0], descriptor=e0)
        far = np.min(mac(self._static_pairs[1], vec), axis=-1) < self.START_MAC
        if far.any():
            lam[far], vec[far] = self._homotopy((e0[far], a0[far]))
        return lam, vec

    def _warm(self, key, e, a):
        """Eigenpairs (speeds, modes), (speeds, n, modes) of one hinge motorcycle continued
        from the nearest hinge evaluated before (all speeds at once, homotopy in the matrices
        from its pencils), or None when there is none near enough or the continuation fails
        or loses the modes (MAC below WARM_MAC)."""
        if not self._cache:
            return None
        distance = [float(np.linalg.norm(key - c[0])) for c in self._cache]
        nearest = int(np.argmin(distance))
        if distance[nearest] > self.WARM_RADIUS:
            return None
        _, e0, a0, lam0, vec0 = self._cache[nearest]
        path = np.linspace(0.0, 1.0, self.WARM_STEPS + 1)
        result = continue_eigenpairs(lambda j: (e0 + path[j] * (e - e0), a0 + path[j] * (a - a0)),
                                     lam0, vec0, speeds=path, keep_vectors=True)
        if not np.all(result.converged) or np.min(result.step_mac) < self.WARM_MAC:
            return None
        return result.eigenvalues[:, -1], result.eigenvectors[:, -1]

    def _over_speed(self, e, a):
        """Eigenpairs of each run, followed over speed from the first speed's."""
        lam0, vec0 = self._start(e[:, 0], a[:, 0])
        result = continue_eigenpairs((e, a), lam0, vec0, speeds=self.grid,
                                     keep_vectors=len(e) == 1)
        if not np.all(result.converged) or np.min(result.step_mac) < 0.5:
            raise ModelError("hinge fit: weave or wobble lost over speed (a hinge far from the "
                             "static one)")
        return result

    def curves(self, runs):
        """{"weave", "wobble"}: eigenvalues (len(runs), speeds) [1/s] for a list of {component:
        Hinge}; ModelError if a mode cannot be followed.

        A single hinge (the simplex's evaluations) is continued in the hinge from the nearest
        one evaluated before when that works (:meth:`_warm`), else over speed."""
        e, a = self.pencil.pencil([self._vehicle_hinges(r) for r in runs], self.grid)
        if len(runs) > 1:
            lam = self._over_speed(e, a).eigenvalues
        else:
            key = self.variables(runs[0])
            warm = self._warm(key, e[0], a[0])
            if warm is None:
                result = self._over_speed(e, a)
                warm = result.eigenvalues[0], result.eigenvectors[0]
            self._cache = (self._cache + [(key, e[0], a[0], *warm)])[-self.CACHE:]
            lam = warm[0][None]
        return {"weave": lam[:, :, 0], "wobble": lam[:, :, 1]}

    def errors(self, runs):
        """[{quantity: e_RMS%}] of each run (list of {component: Hinge}) on ``grid``."""
        reference = {m: c[self._grid] for m, c in self.reference.items()}
        table = _errors(self.curves(runs), reference)
        return [{q: float(table[q][r]) for q in QUANTITIES} for r in range(len(runs))]

    # -- the simplex variables --------------------------------------------------------------
    def variables(self, hinges):
        """Scaled simplex variables per component, concatenated (module docstring)."""
        out = []
        for name in self.names:
            h, ref = hinges[name], self.static[name]
            _, theta0 = _plane(self.sites[name])
            angle = theta0 + h.beta
            root = math.sqrt(ref.k / h.k)
            if self.space == "compliance":
                out += [h.b * root / STEPS["b"], math.cos(angle) * root / STEPS["beta"],
                        math.sin(angle) * root / STEPS["beta"]]
            else:
                out += [h.beta / STEPS["beta"], h.b / STEPS["b"], math.log(h.k) / STEPS["log_k"]]
        return np.array(out)

    def hinges(self, x):
        """{component: Hinge} from scaled variables."""
        out = {}
        for i, name in enumerate(self.names):
            one, two, three = x[3 * i:3 * i + 3]
            if self.space == "compliance":
                _, theta0 = _plane(self.sites[name])
                cos_sin = np.array([two, three]) * STEPS["beta"]
                root = float(np.hypot(*cos_sin))
                k = self.static[name].k / root ** 2
                beta = math.atan2(cos_sin[1], cos_sin[0]) - theta0
                out[name] = hinge_from_line(self.sites[name], beta, one * STEPS["b"] / root, k)
            else:
                out[name] = hinge_from_line(self.sites[name], one * STEPS["beta"],
                                            two * STEPS["b"], math.exp(three * STEPS["log_k"]))
        return out

    def objectives(self, runs, chunk=256):
        """J [%] of each run (list of {component: Hinge}), followed over speed in batches; a
        run whose modes cannot be followed gets J = inf."""
        values = np.full(len(runs), np.inf)
        reference = {m: c[self._grid] for m, c in self.reference.items()}
        for start in range(0, len(runs), chunk):
            part = runs[start:start + chunk]
            e, a = self.pencil.pencil([self._vehicle_hinges(r) for r in part], self.grid)
            lam0, vec0 = self._start(e[:, 0], a[:, 0])
            result = continue_eigenpairs((e, a), lam0, vec0, speeds=self.grid)
            ok = (np.all(result.converged, axis=(1, 2))
                  & (np.min(result.step_mac, axis=(1, 2)) >= 0.5))
            table = _errors({"weave": result.eigenvalues[:, :, 0],
                             "wobble": result.eigenvalues[:, :, 1]}, reference)
            j = np.sqrt(sum(table[q] ** 2 for q in QUANTITIES))
            values[start:start + len(part)] = np.where(ok, j, np.inf)
        return values

    def scan(self, betas, arms, k_factors, chunk=256):
        """J of every hinge (beta, b, k_static x factor) of a grid, per component in turn (the
        others at static): {component: (J array (betas, arms, factors), grid)}; a hinge whose
        modes cannot be followed gets J = inf."""
        out = {}
        for name in self.names:
            grid = [(beta, b, f) for beta in betas for b in arms for f in k_factors]
            runs = [{**self.static, name: hinge_from_line(self.sites[name], beta, b,
                                                          self.static[name].k * f)}
                    for beta, b, f in grid]
            values = self.objectives(runs, chunk)
            out[name] = (values.reshape(len(betas), len(arms), len(k_factors)), grid)
        return out

    def tie_break(self, x):
        """TIE_BREAK times the distance of ``x`` from the static hinges' variables [%]."""
        return TIE_BREAK * float(np.linalg.norm(x - self.variables(self.static)))

    def objective(self, x):
        """J = sqrt(sum of the four e_RMS%^2) [%] plus the tie-break (module docstring); a
        failed tracking counts as very large."""
        self.evaluations += 1
        try:
            errors = self.errors([self.hinges(x)])[0]
        except (ModelError, np.linalg.LinAlgError):
            return _FAILED
        return objective_of(errors) + self.tie_break(x)

    def spring_errors(self, stiffness):
        """{quantity: e_RMS%} on ``grid`` of the chain motorcycle with the 6 x 6 springs
        ``stiffness`` {component: K} (:meth:`HingePencil.spring_pencil`), weave and wobble
        started at the first speed from the eigenvalues nearest the reference's; ModelError if
        they cannot be followed over speed."""
        e, a = self.pencil.spring_pencil(stiffness, self.grid)
        reference = {m: c[self._grid] for m, c in self.reference.items()}
        targets = np.array([reference["weave"][0], reference["wobble"][0]])
        lam0, vec0 = nearest_eigenpairs(a[None, 0], targets, descriptor=e[None, 0])
        result = continue_eigenpairs((e[None], a[None]), lam0, vec0, speeds=self.grid)
        if not np.all(result.converged) or np.min(result.step_mac) < 0.5:
            raise ModelError("the motorcycle with the FE end stiffness: weave or wobble lost "
                             "over speed")
        lam = result.eigenvalues
        table = _errors({"weave": lam[:, :, 0], "wobble": lam[:, :, 1]}, reference)
        return {q: float(table[q][0]) for q in QUANTITIES}

    def conditioning(self, hinges):
        """{component: {label: {quantity: e_RMS%}}} around ``hinges`` (PERTURBATIONS)."""
        runs, labels = [], []
        for name in self.names:
            for label, what, change in PERTURBATIONS:
                runs.append({**hinges, name: perturbed(self.sites[name], hinges[name], what,
                                                       change)})
                labels.append((name, label))
        out = {name: {} for name in self.names}
        for (name, label), errors in zip(labels, self.errors(runs)):
            out[name][label] = errors
        return out


def fit_under_compliance(problem, name, wrench, compliance, betas, arms, xatol=0.05,
                         fatol=0.005):
    """The best hinge of ``name`` whose compliance under ``wrench`` is ``compliance``.

    The fit with the equality w . C_h . w = ``compliance`` [m/N] (the FE model's w . C . w,
    :func:`hinge_compliance`): k follows from the axis and its position, k = (s . w)^2 /
    compliance, and J is minimised over the axis angle and the arm b alone: over the grid
    ``betas`` x ``arms`` [rad, m] (all hinges at once), then by Nelder-Mead from the grid's
    best (steps of 2 deg and 1 cm). The other components keep their static hinges.
    Returns (Hinge, {quantity: e_RMS%}).
    """
    site = problem.sites[name]

    def hinge(beta, b):
        unit = hinge_from_line(site, beta, b, 1.0)
        return hinge_from_line(site, beta, b, hinge_compliance(site, unit, wrench) / compliance)

    def runs(points):
        out = []
        for beta, b in points:
            try:
                out.append({**problem.static, name: hinge(beta, b)})
            except ModelError:                       # an axis along O-q0 has no l
                out.append(None)
        return out

    grid = [(beta, b) for beta in betas for b in arms]
    candidates = runs(grid)
    usable = [i for i, r in enumerate(candidates) if r is not None and r[name].k > 0.0]
    values = problem.objectives([candidates[i] for i in usable])
    start = np.array(grid[usable[int(np.argmin(values))]]) / [STEPS["beta"], STEPS["b"]]

    def objective(x):
        run = runs([x * [STEPS["beta"], STEPS["b"]]])[0]
        if run is None or not run[name].k > 0.0:
            return _FAILED
        try:
            return objective_of(problem.errors([run])[0])
        except (ModelError, np.linalg.LinAlgError):
            return _FAILED

    best = scipy.optimize.minimize(objective, start, method="Nelder-Mead",
                                   options={"xatol": xatol, "fatol": fatol})
    found = hinge(*(best.x * [STEPS["beta"], STEPS["b"]]))
    return found, problem.errors([{**problem.static, name: found}])[0]


def _coarse_index(n, step):
    """Every ``step``-th speed index, the last one included."""
    index = np.arange(0, n, max(int(step), 1))
    return index if index[-1] == n - 1 else np.append(index, n - 1)


def objective_of(errors):
    """The fit's objective [%]: root of the sum of the squared e_RMS% of the four quantities."""
    return math.sqrt(sum(errors[q] ** 2 for q in QUANTITIES))


def _simplex_search(problem, x0, first_step, xatol, fatol, limit, restarts):
    """Nelder-Mead from x0 (first simplex edge ``first_step``), restarted from its best point
    with a unit simplex while that improves J by more than fatol."""
    best = None
    for attempt in range(restarts + 1):
        step = first_step if attempt == 0 else 1.0
        simplex = np.vstack([x0, x0 + step * np.eye(len(x0))])
        left = limit - problem.evaluations
        if left <= len(x0) + 1:
            break
        run = scipy.optimize.minimize(problem.objective, x0, method="Nelder-Mead",
                                      options={"initial_simplex": simplex, "xatol": xatol,
                                               "fatol": fatol, "maxfev": left})
        improved = best is None or run.fun < best.fun - fatol
        if best is None or run.fun < best.fun:
            best = run
        if not improved:
            break
        x0 = best.x
    return best


def fit_hinges(vehicle, components, identified, names, reference, speeds, starts=None,
               max_evaluations=None, xatol=0.1, fatol=0.01, restarts=1, first_step=5.0,
               coarse_speeds=12):
    """Fit one hinge per component of ``names`` to the flexible reference (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        The rigid motorcycle.
    components : mapping
        {component name: structures Component} placed in it.
    identified : mapping
        Identification results (the static hinges the search starts from).
    names : sequence of str
        Components with a fitted hinge; several are fitted jointly.
    reference : mapping
        {"weave", "wobble"}: eigenvalues over ``speeds`` of the flexible motorcycle [1/s].
    speeds : array
        Speeds [m/s] (the paper: 40-210 km/h).
    starts : mapping, optional
        More starting points {label: {component: Hinge}} besides the static identification
        (e.g. the hinges of the road_load and vehicle_load bench tests); the search runs from
        the static one and from the one of these with the lowest J as it is.
    max_evaluations : int, optional
        Objective evaluations allowed per start (default 300 per component).
    xatol, fatol : float
        Nelder-Mead tolerances on the scaled variables and on J [%].
    restarts : int
        Nelder-Mead restarts from the best point (a fresh unit simplex) while they improve J.
    first_step : float
        Edge of the first simplex in scaled variables (5: 10 deg, 5 cm, 50 % of k).
    coarse_speeds : int
        The search from each start runs on about this many of the speeds (every n-th, the
        last included); the best end point is then polished on all speeds.

    Returns
    -------
    HingeFit

    """
    clock = time.perf_counter()
    problem = HingeFitProblem(vehicle, components, identified, names, reference, speeds)
    limit = max_evaluations or 300 * len(problem.names)
    others = {label: {n: hinges.get(n, problem.static[n]) for n in problem.names}
              for label, hinges in (starts or {}).items()}
    step = max(1, round(len(problem.speeds) / coarse_speeds))
    coarse = problem.on_speeds(_coarse_index(len(problem.speeds), step))
    candidates = {"static": dict(problem.static)}
    if others:       # the other start that fits best as it is (one batched evaluation)
        labels = list(others)
        first = [objective_of(e) for e in coarse.errors([others[k] for k in labels])]
        candidates[labels[int(np.argmin(first))]] = others[labels[int(np.argmin(first))]]
    ends, evaluations = {}, 0
    for label, hinges in candidates.items():
        coarse.evaluations = 0
        ends[label] = _simplex_search(coarse, coarse.variables(hinges), first_step, xatol,
                                      fatol, limit, restarts)
        evaluations += coarse.evaluations
    winner = min(ends, key=lambda label: ends[label].fun)
    best = _simplex_search(problem, ends[winner].x, 1.0, xatol, fatol, limit, restarts)
    problem.evaluations += evaluations
    hinges = problem.hinges(best.x)
    static_errors, errors = problem.errors([problem.static, hinges])
    conditioning = problem.conditioning(hinges)
    try:
        spring = problem.spring_errors({n: np.linalg.inv(end_compliance(components[n]))
                                        for n in problem.names})
    except ModelError:
        spring = None
    searched = {label: {"objective": float(end.fun) - coarse.tie_break(end.x),
                        "hinges": {n: h.to_dict() for n, h in problem.hinges(end.x).items()}}
                for label, end in ends.items()}
    return HingeFit(problem.names, hinges, dict(problem.static), errors, static_errors,
                    objective_of(errors), conditioning, problem.evaluations,
                    time.perf_counter() - clock, "jointly" if len(problem.names) > 1
                    else "single", problem.speeds, winner, searched, spring)
