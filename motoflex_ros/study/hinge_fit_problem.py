"""The hinge fit's evaluations: hinges -> weave and wobble over speed -> e_RMS% (eq. 18).

The objective of the fit (:mod:`motoflex_ros.study.fitted`) is

    J = sqrt(sum over weave f, weave Re, wobble f, wobble Re of e_RMS%^2)  [%]
        (eq. 18 over the speeds given, the paper's 40-210 km/h)

against the flexible motorcycle's weave and wobble, the rest of the lumped motorcycle being the
static variant's (inertia distribution of Sect. 5.2). The simplex variables are the hinge's
compliance vector at q0 in the antisymmetric motions (u_y, theta_x, theta_z),
v = (b, cos theta, sin theta) / sqrt(k), scaled by the static hinge's (steps of 1 cm, 2 deg
and 10 % of k, in size); theta = theta_0 + beta is the axis direction, b the signed arm of q0
((L - l) sin beta, eq. 7). Every evaluation is cheap: the hinge motorcycle's pencils come from
one linearization for any hinge (:class:`~motoflex_ros.study.hinge_pencil.HingePencil`);
weave and wobble are continued (:mod:`motoflex_ros.study.continuation`) in the hinge from the
nearest hinge evaluated before, all speeds at once, or else over speed from the first speed,
where they start from the static motorcycle's (named by mode shape by the engine).

Tie-break: the simplex minimises J + TIE_BREAK |x - x_static| (x the scaled variables, so the
distance is in steps of 2 deg, 1 cm, 10 % of k). Where weave and wobble see the hinge only
through one combination of its parameters (the frame: the steering head's lateral compliance
b^2/k) J alone slides towards b -> 0, k -> 0 (the head sliding sideways without turning, no
hinge; |x| grows as 1/sqrt(k)); the term keeps the fit a hinge and pulls it towards the bench
identification. It does not make a flat valley's answer unique (the frame's search ends at
40 or 124 deg to O-q0 depending on the start, test_study_fitted). Where weave and wobble see
all three parameters it moves the optimum by thousandths of a step (J's curvature is
0.3-5 % per step^2). The J reported is without it.

Besides the hinges, the lumped motorcycle with the component's whole end stiffness in the
hinge's place (:meth:`HingePencil.spring_pencil`, K = C^-1 of the clamped FE model, massless)
is evaluated the same way (:meth:`HingeFitProblem.spring_errors`): what any stiffness at that
place can reach, against which the single hinge is judged.

Conditioning of the optimum: e_RMS% with one of k +-10 %, the axis turned +-2 deg about its
point nearest q0 (b kept), or the axis moved +-1 cm normal to itself in the symmetry plane
(b +-1 cm), the rest at the optimum.
"""
import math

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.study.accuracy import QUANTITIES, weave_wobble_errors
from motoflex_ros.study.continuation import continue_eigenpairs, mac, nearest_eigenpairs
from motoflex_ros.study.hinge_geometry import (
    hinge_from_line,
    hinge_line,
    perturbed,
    site_plane,
    static_hinge,
)
from motoflex_ros.study.hinge_pencil import HingePencil
from motoflex_ros.study.tracked import HomotopyStart
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["HingeFitProblem", "objective_of", "STEPS", "PERTURBATIONS", "TIE_BREAK",
           "FAILED_OBJECTIVE"]

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
FAILED_OBJECTIVE = 1e12
"""Objective of a hinge whose modes cannot be followed (continuation failed)."""


def objective_of(errors):
    """The fit's objective [%]: root of the sum of the squared e_RMS% of the four quantities."""
    return math.sqrt(sum(errors[q] ** 2 for q in QUANTITIES))


class HingeFitProblem:
    """The hinge fit's evaluations: hinges -> weave and wobble over speed -> e_RMS%.

    Parameters
    ----------
    vehicle, components, identified
        As :func:`motoflex_ros.study.identified_variants.build_variant`.
    names : sequence of str
        The components with a fitted hinge (the others rigid, as in the accuracy study).
    reference : mapping
        {"weave": complex (speeds,), "wobble": ...} of the flexible motorcycle [1/s].
    speeds : array
        Speeds [m/s] of ``reference``.
    tie_break : float
        Weight [% per scaled step] of the distance from the static hinges in
        :meth:`objective` (default TIE_BREAK; module docstring).

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

    def __init__(self, vehicle, components, identified, names, reference, speeds,
                 tie_break=TIE_BREAK):
        self.tie_break_weight = float(tie_break)
        self.names = tuple(names)
        self.speeds = np.asarray(speeds, float)
        self.reference = {m: np.asarray(reference[m], complex) for m in STUDIED_MODES}
        for mode, curve in self.reference.items():
            if curve.shape != self.speeds.shape or not np.all(np.isfinite(curve)):
                raise ModelError(f"the flexible reference's {mode} must be tracked at every "
                                 f"one of the {len(self.speeds)} speeds")
        self.sites = {n: lumped.site_of(components[n]) for n in self.names}
        self.static = {n: static_hinge(identified, n, self.sites[n]) for n in self.names}
        self.pencil = HingePencil(vehicle, components, identified, self.names)
        sweep = modal_sweep(linearize(self.pencil.base), self.speeds[:1])
        targets = tuple(complex(sweep.modes[m][0]) for m in STUDIED_MODES)
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
        table = weave_wobble_errors(self.curves(runs), reference)
        return [{q: float(table[q][r]) for q in QUANTITIES} for r in range(len(runs))]

    # -- the simplex variables --------------------------------------------------------------
    def variables(self, hinges):
        """Scaled simplex variables per component, concatenated (module docstring)."""
        out = []
        for name in self.names:
            h, ref = hinges[name], self.static[name]
            _, theta0 = site_plane(self.sites[name])
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
                _, theta0 = site_plane(self.sites[name])
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
            table = weave_wobble_errors({"weave": result.eigenvalues[:, :, 0],
                                         "wobble": result.eigenvalues[:, :, 1]}, reference)
            j = np.sqrt(sum(table[q] ** 2 for q in QUANTITIES))
            values[start:start + len(part)] = np.where(ok, j, np.inf)
        return values

    def tie_break(self, x):
        """The tie-break weight times the distance of ``x`` from the static hinges' variables
        [%]."""
        return self.tie_break_weight * float(np.linalg.norm(x - self.variables(self.static)))

    def objective(self, x):
        """J = sqrt(sum of the four e_RMS%^2) [%] plus the tie-break (module docstring); a
        failed tracking counts as very large."""
        self.evaluations += 1
        try:
            errors = self.errors([self.hinges(x)])[0]
        except (ModelError, np.linalg.LinAlgError):
            return FAILED_OBJECTIVE
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
        table = weave_wobble_errors({"weave": lam[:, :, 0], "wobble": lam[:, :, 1]}, reference)
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
