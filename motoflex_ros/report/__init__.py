"""Run reports: bags/<run>/report.html built from the JSON outputs of the motoflex verbs."""
