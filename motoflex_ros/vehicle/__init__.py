"""Vehicle engine: one multibody description for every two-wheeler variant.

A vehicle is a tree of bodies on a 6-DOF floating base, joined by one-DOF joints (revolute about
any axis through any point, prismatic), with wheels that roll either without slip (knife edge)
or through tyres with relaxation. The engine linearizes the equations of motion about upright,
straight running at speed v and returns the descriptor pencil E(v) x' = A(v) x, polynomial in v.

Modules (vector helpers: :mod:`motoflex_ros.spatial`): ``model`` (dataclasses and derived body
data), ``schema`` (YAML validation), ``kinematics`` (tree kinematics), ``contact`` (rolling
contact on the toroidal tyre), ``tyre`` (linear and Magic Formula tyres), ``dynamics`` (Kane
residual), ``linearize`` (complex-step linearization, speed polynomial), ``modes`` (MAC tracking
of weave/wobble/capsize; their names in ``mode_names``, light to import), ``steer_pulse``
(steer-pulse response), ``superelement`` (Craig-Bampton superelements with one or several
ends, bushings), ``flexible_bodies`` (a beam component as the paper's flexible bodies:
per-body superelements, bushings, spherical links, clamp welds),
``flexible_motorcycle`` (the touring motorcycle's per-body map: its flexible bodies joined by
the vehicle's joints, ``--flex flexible_bodies``), ``outline`` (where each body holds its joints
and wheels, for viewers).

Public API::

    model = load_vehicle(path)                 # or vehicle_from_dict(data, source)
    lin = linearize(model)                     # LinearVehicle; E(v), A(v) polynomial in v
    E, A = lin.pencil(speeds)                  # stacked descriptor pencil
    A_s = lin.state_matrix(speeds)             # E^-1 A (regular E only)
    lin.eigenvalues(v)                         # finite eigenvalues (QZ; massless bodies ok)
    lin.second_order()                         # M, C0, C1, K0, K2 (knife-edge wheels)
    sweep = modal_sweep(lin, speeds)           # weave, wobble, capsize tracked by MAC
    steer_pulse_response(lin, v)               # poles back: identify.matrix_pencil

Variants edit the model, never the engine: bodies (massless ones too), joints and wheels are
plain frozen dataclasses (dataclasses.replace), and ``VehicleModel.elements`` takes force
elements whose ``generalized_residual(system, frames, q, u, udot)`` is added to the equations
of motion (superelement stiffness, damping and inertia coupling on joint or modal coordinates).

Also: ``loops`` (closed loops as constraints), ``lumped`` (the paper's lumped variants as edits
of one description), ``variants`` (variant names, the flexible ground truth),
``nonlinear_response`` (the nonlinear road test), ``poses`` (body poses
along a response), ``animation`` (mode shapes and road test as poses for viewers).
"""
