"""Vehicle engine: one multibody description for every two-wheeler variant.

A vehicle is a tree of bodies on a 6-DOF floating base, joined by one-DOF joints (revolute about
any axis through any point, prismatic), with wheels that roll either without slip (knife edge)
or through tyres with relaxation. The engine linearizes the equations of motion about upright,
straight running at speed v and returns the descriptor pencil E(v) x' = A(v) x, polynomial in v.

Modules: ``spatial`` (complex-safe vector helpers), ``model`` (dataclasses and derived body
data), ``schema`` (YAML validation), ``kinematics`` (tree kinematics), ``contact`` (rolling
contact on the toroidal tyre), ``tyre`` (linear and Magic Formula tyres), ``dynamics`` (Kane
residual), ``linearize`` (complex-step linearization, speed polynomial), ``modes`` (MAC tracking
of weave/wobble/capsize), ``response`` (steer-pulse response, matrix pencil).
"""
