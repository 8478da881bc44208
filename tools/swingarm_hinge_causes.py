"""Why the swingarm's "bending" hinge fits the flexible motorcycle better than "static" (issue 12).

Usage: python tools/swingarm_hinge_causes.py [--step-kmh 10]

A measurement, not a test (its numbers are quoted in the reason of the strict xfail
test_study_accuracy.py::test_published_static_lowest_error_in_every_case[swingarm]). Against the
flexible motorcycle with the swingarm flexible, e_RMS % (eq. 18) of weave and wobble over
40-210 km/h for:

1. the candidates, one at a time: the static hinge with the bending model's inertia J (eq. 10)
   on the massless body or its damping c (eq. 11) or its stiffness k; the bending hinge with
   the static model's J = 0 and c = gamma k; the static hinge hung from the main arm instead of
   the wheel carrier; the wheel carrier's mass moved onto the massless body;
2. the flexible swingarm as its Guyan condensation at q0 (no modes), with the compliance
   coupling lateral (u_y, r_x, r_z) and in-plane motion zeroed;
3. that reference with the lateral compliance block replaced by the hinge's own (rank one,
   s s^T / k) plus the FE's remainder on roll r_x, yaw r_z or both: which of the FE's
   compliances the hinge lacks, and what each costs.
"""
import argparse
from dataclasses import replace

import numpy as np

from motoflex_ros.bench.offline_campaign import identify_components
from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component, load_components
from motoflex_ros.inertia import composite_inertia
from motoflex_ros.study.identified_variants import GAMMA
from motoflex_ros.study.lumped_accuracy import _weave_wobble, flexible_reference, mode_errors
from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.lumped import FlexJoint, axis_in_vehicle, lumped_vehicle
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.superelement import superelement_of
from motoflex_ros.vehicle.variants import flexible_vehicle

LAT, INPLANE = [1, 3, 5], [0, 2, 4]      # end DOFs (u_x, u_y, u_z, r_x, r_y, r_z) at q0


class Study:
    def __init__(self, speeds):
        self.speeds = speeds
        self.vehicle = load_vehicle(config_path("vehicles", "touring"))
        self.comp = load_component("swingarm")
        self.site = lumped.site_of(self.comp)
        runs = identify_components(load_components(["swingarm"]))
        self.ident = {n: run.identification.to_dict() for n, (_, run) in runs.items()}
        self.flexible = flexible_reference(self.vehicle, {"swingarm": self.comp}, self.ident,
                                           ["swingarm"], speeds)

    def hinge(self, source, k=None, c=None, J=0.0):
        """FlexJoint on the (l, beta) of identified test ``source``; k, c default to that
        test's k and the static model's c = gamma k."""
        found = self.ident["swingarm"][source]
        point, axis = axis_in_vehicle(self.site, found["l"], found["beta"])
        k = found["k"] if k is None else k
        return FlexJoint("swingarm_hinge", point, axis, k, GAMMA * k if c is None else c, J)

    def twist(self, source):
        """Unit twist at q0 (translation, rotation) over sqrt(k) of a hinge: C_h = s s^T."""
        fj = self.hinge(source)
        r = self.site.origin + self.site.q0 - fj.point
        return np.r_[np.cross(fj.axis, r), fj.axis] / np.sqrt(fj.k)

    def curves(self, model):
        return _weave_wobble(model, self.speeds)

    def lumped(self, fj, inertia_from="static"):
        return lumped_vehicle(self.vehicle, inertia_from, {"swingarm": (fj,)})

    def flexible_with(self, element):
        return self.curves(flexible_vehicle(self.vehicle, {"swingarm": element}))


def carrier_on_moving_side(model):
    """The lumped ``model`` with the wheel carrier's mass on the massless body (as the front
    models move the lower fork)."""
    bodies = {b.name: b for b in model.bodies}
    carrier, moving = bodies["wheel_carrier"], bodies["rear_flex"]
    mass, com, inertia = composite_inertia([(b.mass, b.com, b.inertia)
                                            for b in (carrier, moving)])
    bodies["rear_flex"] = replace(moving, mass=mass, com=com, inertia=inertia)
    bodies["wheel_carrier"] = replace(carrier, mass=0.0, inertia=np.zeros((3, 3)))
    return replace(model, bodies=tuple(bodies.values()))


def line(label, errors):
    print(f"{label:62s} total {sum(errors.values()):6.3f}  "
          + "  ".join(f"{q} {v:6.3f}" for q, v in errors.items()), flush=True)


def candidates(st):
    bending = st.ident["swingarm"]["bending"]
    hinge_models = {
        "static (paper)": st.lumped(st.hinge("static")),
        "bending (paper)": st.lumped(st.hinge("bending", c=bending["c"], J=bending["J"]),
                                     "bending"),
        "static hinge + bending's J on the massless body": st.lumped(
            st.hinge("static", J=bending["J"]), "bending"),
        "static hinge + bending's c": st.lumped(st.hinge("static", c=bending["c"])),
        "static hinge + bending's k": st.lumped(st.hinge("static", k=bending["k"])),
        "bending hinge, static's J = 0 and c = gamma k": st.lumped(st.hinge("bending")),
        "static hinge + the wheel carrier on the moving side": carrier_on_moving_side(
            st.lumped(st.hinge("static"))),
    }
    for label, model in hinge_models.items():
        line(label, mode_errors(st.curves(model), st.flexible, label))
    donor = lumped.MOUNTS["swingarm"]
    lumped.MOUNTS["swingarm"] = ("swingarm", donor[1])
    try:
        model = st.lumped(st.hinge("static"))
    finally:
        lumped.MOUNTS["swingarm"] = donor
    line("static hinge hung from the main arm", mode_errors(st.curves(model), st.flexible, ""))


def compliance_split(st):
    guyan = superelement_of(st.comp, "swingarm", n_modes=0,
                            follows=lumped.SUPERELEMENT_FOLLOWS["swingarm"])
    fe = np.linalg.inv(guyan.K)
    fe[np.ix_(LAT, INPLANE)] = 0.0
    fe[np.ix_(INPLANE, LAT)] = 0.0
    line("Guyan (no modes) vs flexible", mode_errors(st.flexible_with(guyan), st.flexible, ""))
    decoupled = st.flexible_with(replace(guyan, K=np.linalg.inv(fe)))
    line("Guyan, lateral/in-plane decoupled vs flexible",
         mode_errors(decoupled, st.flexible, ""))
    block = fe[np.ix_(LAT, LAT)]
    print("FE lateral compliance at q0 (u_y, r_x, r_z) [um/N, urad/(N m)] diagonal:",
          np.round(np.diag(block) * 1e6, 3))
    for name, inertia_from in (("static", "static"), ("bending", "bending")):
        found = st.ident["swingarm"][name]
        c = found["c"] if name == "bending" else None
        hinge = st.curves(st.lumped(st.hinge(name, c=c, J=found.get("J", 0.0)), inertia_from))
        s = st.twist(name)[LAT]
        own = np.outer(s, s)
        rest = block - own
        print(f"{name} hinge diagonal {np.round(np.diag(own) * 1e6, 3)}; yaw "
              f"{own[2, 2] / block[2, 2]:.3f} of the FE's")
        line(f"  {name} vs the decoupled Guyan", mode_errors(hinge, decoupled, ""))
        for label, keep in (("nothing", []), ("roll r_x", [1]), ("yaw r_z", [2]),
                            ("roll and yaw", [1, 2])):
            mix = fe.copy()
            mask = np.zeros((3, 3))
            mask[np.ix_(keep, keep)] = 1.0
            mix[np.ix_(LAT, LAT)] = own + mask * rest + 1e-10 * np.eye(3)
            reference = st.flexible_with(replace(guyan, K=np.linalg.inv(mix)))
            line(f"  {name} vs its own hinge + the FE's rest on {label}",
                 mode_errors(hinge, reference, ""))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--step-kmh", type=float, default=10.0)
    args = ap.parse_args()
    st = Study(kmh_to_ms(np.arange(40.0, 210.0 + 1e-9, args.step_kmh)))
    candidates(st)
    compliance_split(st)


if __name__ == "__main__":
    main()
