"""Measured bench records made without the package's bench code (issue 17), for the tests of
``motoflex identify --measured``: closed-form responses, numpy and scipy only.

- :func:`cantilever_record`: a straight cantilever tube along x (Euler-Bernoulli), loaded
  sideways (F_y) at its tip through a cosine ramp, a hold and a ramp down; the tip's markers
  follow the closed-form static deflection y = F L^3 / (3 E I) and rotation
  theta_z = F L^2 / (2 E I). Closed-form identification: the deformed plane's normal is
  (-sin theta, cos theta, 0), so the axis meets the tube at l = L - y cot(theta) = L / 3, is
  normal to it (beta = pi / 2), b = 2 L / 3 and k = F b / asin(y / b) = 4 E I / (3 L).
- :func:`hinge_record`: a rigid arm on a revolute hinge (one degree of freedom: J theta'' +
  c theta' + k theta = F b) with a static test, a harmonic test at its natural frequency and a
  release from a preload; the loaded end and its markers turn about the hinge axis exactly.
"""
import math

import numpy as np
import scipy.linalg as sla

PLATE = np.array([[0.08, 0.0, 0.0], [-0.04, 0.07, 0.0], [-0.04, -0.07, 0.0],
                  [0.0, 0.0, 0.08]])


def tube_bending_stiffness(e_pa=2.1e11, d_m=0.04, t_m=0.002):
    """E I [N m^2] of a circular tube of outer diameter d and wall t."""
    return e_pa * math.pi / 64.0 * (d_m**4 - (d_m - 2 * t_m) ** 4)


def _cosine(t, t0, duration):
    """0 -> 1 cosine ramp over [t0, t0 + duration]."""
    x = np.clip((t - t0) / duration, 0.0, 1.0)
    return 0.5 * (1.0 - np.cos(np.pi * x))


def cantilever_record(length=0.6, force=100.0, rate=1000.0, noise_m=0.0, load_noise_n=0.0,
                      seed=1, lead_in_s=0.2, markers=PLATE):
    """(t, wrench (n, 6), markers (n, N, 3), expected {l, beta, b, k}, q0) of the cantilever."""
    ei = tube_bending_stiffness()
    t = np.arange(0.0, lead_in_s + 0.3 + 0.5 + 0.3 + 0.3, 1.0 / rate)
    up = _cosine(t, lead_in_s, 0.3)
    down = _cosine(t, lead_in_s + 0.8, 0.3)
    f = force * (up - down)
    y = f * length**3 / (3.0 * ei)
    theta = f * length**2 / (2.0 * ei)
    q0 = np.array([length, 0.0, 0.0])
    c, s = np.cos(theta), np.sin(theta)
    rot = np.zeros((len(t), 3, 3))
    rot[:, 0, 0], rot[:, 0, 1], rot[:, 1, 0], rot[:, 1, 1], rot[:, 2, 2] = c, -s, s, c, 1.0
    tip = np.column_stack([np.full(len(t), length), y, np.zeros(len(t))])
    points = tip[:, None, :] + np.einsum("nij,mj->nmi", rot, markers)
    rng = np.random.default_rng(seed)
    points = points + noise_m * rng.standard_normal(points.shape)
    wrench = np.zeros((len(t), 6))
    wrench[:, 1] = f + load_noise_n * rng.standard_normal(len(t))
    expected = {"l": length / 3.0, "beta": math.pi / 2.0, "b": 2.0 * length / 3.0,
                "k": 4.0 * ei / (3.0 * length)}
    return t, wrench, points, expected, q0


def _rotation(axis, angle):
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def _simulate(t, force, k, c, inertia, arm):
    """theta(t) of J theta'' + c theta' + k theta = F(t) b, exact for a piecewise-linear load
    (first-order hold), from rest."""
    a = np.array([[0.0, 1.0], [-k / inertia, -c / inertia]])
    bvec = np.array([0.0, arm / inertia])
    out = np.zeros(len(t))
    z = np.zeros(2)
    cache = {}
    for i in range(1, len(t)):
        dt = round(t[i] - t[i - 1], 12)
        if dt not in cache:
            aug = np.zeros((4, 4))
            aug[:2, :2], aug[:2, 2], aug[2, 3] = a, bvec, 1.0 / dt
            e = sla.expm(aug * dt)
            cache[dt] = (e[:2, :2], e[:2, 2] - e[:2, 3], e[:2, 3])
        phi, g0, g1 = cache[dt]
        z = phi @ z + g0 * force[i - 1] + g1 * force[i]
        out[i] = z[0]
    return out


def hinge_record(l_true=0.25, beta_deg=60.0, k=2.0e4, f_n=20.0, zeta=0.02, force=50.0,
                 rate=1000.0, noise_m=0.0, seed=2):
    """(t, wrench, markers, truth, q0) of the hinge (module doc): truth has l, beta, b, k, J,
    c, omega_n, zeta."""
    q0 = np.array([0.6, 0.0, 0.2])
    length = float(np.hypot(q0[0], q0[2]))
    e0 = np.array([q0[0], 0.0, q0[2]]) / length
    beta = math.radians(beta_deg)
    theta0 = math.atan2(q0[2], q0[0]) + beta
    axis = np.array([math.cos(theta0), 0.0, math.sin(theta0)])
    hinge = l_true * e0
    arm = (length - l_true) * math.sin(beta)
    omega = 2 * math.pi * f_n
    inertia = k / omega**2
    damping = 2.0 * zeta * inertia * omega
    dt = 1.0 / rate
    pieces, t_end = [], 0.0

    def add(duration, func):
        nonlocal t_end
        tt = t_end + dt * np.arange(1, int(round(duration * rate)) + 1)
        pieces.append((tt, func(tt - t_end)))
        t_end = tt[-1]

    pieces.append((np.array([0.0]), np.array([0.0])))
    add(0.2, lambda s: 0 * s)                                       # lead-in
    add(0.5, lambda s: force * _cosine(s, 0.0, 0.5))                # static ramp
    add(0.5, lambda s: force + 0 * s)                               # hold
    add(0.5, lambda s: force * (1 - _cosine(s, 0.0, 0.5)))          # ramp down
    add(1.0, lambda s: 0 * s)                                       # rest
    onset = 3.0 / f_n
    periods = 4.0 / (zeta * omega) * f_n + 40
    add(onset + periods / f_n,
        lambda s: 0.2 * force * _cosine(s, 0.0, onset) * np.sin(omega * s))  # harmonic
    add(1.0, lambda s: 0 * s)                                       # rest
    add(0.5, lambda s: 2 * force * _cosine(s, 0.0, 0.5))            # preload
    add(0.3, lambda s: 2 * force + 0 * s)                           # held
    add(2.0, lambda s: 0 * s)                                       # released: free decay
    t = np.concatenate([p[0] for p in pieces])
    f = np.concatenate([p[1] for p in pieces])
    theta = _simulate(t, f, k, damping, inertia, arm)
    # the sign of theta: a positive F_y turns q0 towards +y
    sign = 1.0 if np.cross(axis, q0 - hinge)[1] > 0 else -1.0
    rng = np.random.default_rng(seed)
    points = np.zeros((len(t), len(PLATE), 3))
    for i, angle in enumerate(theta):
        rot = _rotation(axis, sign * angle)
        points[i] = hinge + (q0 + PLATE - hinge) @ rot.T
    points = points + noise_m * rng.standard_normal(points.shape)
    wrench = np.zeros((len(t), 6))
    wrench[:, 1] = f
    truth = {"l": l_true, "beta": beta, "b": arm, "k": k, "J": inertia, "c": damping,
             "omega_n": omega, "zeta": zeta}
    return t, wrench, points, truth, q0


def bench_yaml(name, q0, markers=PLATE, noise_m=5e-6, latency_s=0.0):
    """Text of a bench file (markers: offsets, or a string such as 'from_data')."""
    if isinstance(markers, str):
        marker_text = markers
    else:
        marker_text = "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in m) + "]"
                                      for m in markers) + "]"
    return (f"bench: {name}\nloaded_end: [{', '.join(repr(float(v)) for v in q0)}]\n"
            f"markers: {marker_text}\nsensor: {{noise_m: {noise_m!r}, latency_s: "
            f"{latency_s!r}}}\n")


def verb_script(argv, blocked=("motoflex_ros.structures", "motoflex_ros.bench.offline_campaign")):
    """Python source that runs ``motoflex identify`` with ``argv`` (the verb registered alone:
    the ``motoflex`` parser imports every verb, the eigenvalue verb the vehicle and its
    structures) with the ``blocked`` packages made unimportable, and asserts that no
    structures module got loaded; exits with the verb's code."""
    return ("import sys, argparse\n"
            f"for name in {tuple(blocked)!r}:\n"
            "    sys.modules[name] = None\n"
            "from motoflex_ros.cli import identify\n"
            "parser = argparse.ArgumentParser()\n"
            "identify.register(parser.add_subparsers())\n"
            f"code = identify.run(parser.parse_args(['identify', *{list(map(str, argv))!r}]))\n"
            "assert not [m for m, v in sys.modules.items()\n"
            "            if v is not None and m.startswith('motoflex_ros.structures')]\n"
            "sys.exit(code)\n")


def compliance_record(compliance, q0, moment_directions, force=100.0, moment=20.0, rate=1000.0,
                      markers=PLATE):
    """(t, wrench (n, 6), markers (n, N, 3)) of a loaded end whose out-of-plane motion
    (u_y [m], theta_x, theta_z [rad]) is ``compliance`` (3 x 3) times (F_y [N], M_x, M_z [N m]):
    a static test of F_y, then one of a moment ``moment`` along each unit direction of
    ``moment_directions`` (in the x-z plane), each a cosine ramp, a hold and a ramp down. The
    markers move rigidly with the end: q0 + (0, u_y, 0) + R(theta) offset (Rodrigues)."""
    loads = [np.array([0.0, force, 0.0, 0.0, 0.0, 0.0])]
    loads += [np.concatenate([np.zeros(3), moment * np.asarray(d, float)])
              for d in moment_directions]
    test_s, lead_in_s = 1.4, 0.2
    t = np.arange(0.0, lead_in_s + test_s * len(loads), 1.0 / rate)
    wrench = np.zeros((len(t), 6))
    for j, load in enumerate(loads):
        start = lead_in_s + j * test_s
        shape = _cosine(t, start, 0.3) - _cosine(t, start + 0.8, 0.3)
        wrench += shape[:, None] * load[None, :]
    motion = wrench[:, [1, 3, 5]] @ np.asarray(compliance, float).T   # (u_y, theta_x, theta_z)
    points = np.empty((len(t), len(markers), 3))
    for n, (u_y, theta_x, theta_z) in enumerate(motion):
        theta = np.array([theta_x, 0.0, theta_z])
        angle = float(np.linalg.norm(theta))
        rot = _rotation(theta / angle, angle) if angle else np.eye(3)
        points[n] = np.asarray(q0, float) + np.array([0.0, u_y, 0.0]) + markers @ rot.T
    return t, wrench, points
