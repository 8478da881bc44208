"""The ``motoflex`` command: one module per verb, each calling the pure core directly.

Verbs: ``bag``, ``campaign`` (with ``campaign_summary``, what it prints at the end),
``compare``, ``components``, ``eig``, ``identify``, ``replay``, ``report``, ``rerun``,
``study`` (with ``study_accuracy`` and
``study_design``), ``view``; ``main`` dispatches. Shared: ``inputs``
(identification results and placed components), ``options`` (flags), ``output`` (JSON,
tables, --force), ``recording`` (a run folder's rerun recording).
"""
