"""Process orchestration of the rig: every node a separate process on its own ROS domain.

Modules: ``campaign_graph`` (the bench campaign as a node graph, and its outcome), ``graph``
(nodes as processes), ``run`` (a graph run to its end) with ``run_failures`` (why it failed)
and ``monitor`` (the campaign process's own node), ``domain`` (a free ROS_DOMAIN_ID),
``interrupts`` (SIGINT/SIGTERM), ``provenance`` and ``status`` (provenance.json and
status.json of a run folder).
"""
