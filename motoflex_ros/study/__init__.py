"""Studies on top of the vehicle engine (Passigato et al. 2023, Sects. 4.3, 5.2, 5.3).

stability_index (eqs. 13-15), factorial (designs), anova, correlation (eqs. 16-17), accuracy
(eq. 18), continuation (tracking modes over speed), tracked (the vehicle-to-study plug: study
functions from state matrices or linear stiffness pencils), runner (in process or on Dask),
sensitivity (the analysis of Sect. 5.3) and motorcycle (that study on the engine's decomposed
lumped motorcycle). Submodules are imported explicitly; this package imports nothing heavy.

Also: identified_variants (the paper's lumped variants from identification results),
load_variants (hinges from vehicle-like bench loads), vehicle_load (the wrench a component
carries in a mode), fitted and hinge_pencil (a hinge fitted to the flexible motorcycle, with
hinge_geometry, hinge_fit_problem and hinge_fit_result),
lumped_accuracy (Sect. 5.2), flexible_sensitivity and tilt_stiffness (sensitivities of the
flexible motorcycle), pulse_check (eigenvalues checked in the time domain), verdict (the
least-damped point of each mode); design_space, design_update, design_evaluate,
design_search and design_study (``motoflex study design``: sections for stability at least
mass, beyond the paper).
"""
