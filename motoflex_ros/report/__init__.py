"""Run reports: bags/<run>/report.html built from the JSON outputs of the motoflex verbs.

Modules: ``build`` (report.html), ``sources`` (the verbs' JSON per run folder), ``run_folder``
(what a run folder is), ``summary`` (the opening section), ``provenance_section`` (how the run
was made), ``tables``, ``design_tables`` (the design
study's section), ``figures``, ``html``, ``published`` (published values set beside ours).
"""
