"""How figures and tables name model variants and compared quantities (no matplotlib here, so
the report's tables can use the same names)."""

__all__ = ["VARIANT_LABELS", "QUANTITY_LABELS"]

VARIANT_LABELS = {"flexible": "flexible (Craig-Bampton)",
                  "state_of_the_art": "state of the art (Sect. 5.2.1-5.2.3)",
                  "static": "static axis", "torsion": "torsion axis", "bending": "bending axis",
                  "decomposed": "decomposed (eq. 12)", "rigid": "rigid",
                  "fitted": "fitted hinge", "road_load": "road-load test axis",
                  "vehicle_load": "vehicle-load test axis",
                  "principal": "principal hinges (bench, F_y + 2 moments)"}
"""How figures and tables name the model variants (Sect. 5.2; fitted, road_load, vehicle_load:
issue 14; principal: issue 22)."""
QUANTITY_LABELS = {"weave_f": "weave frequency", "weave_re": "weave real part",
                   "wobble_f": "wobble frequency", "wobble_re": "wobble real part"}
"""How figures and tables name the compared quantities of eq. (18)."""
