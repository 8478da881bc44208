#!/usr/bin/env bash
# The test command of the README: installs what it needs on first use (.venv), then runs the
# linter and the whole test suite. Extra arguments go to pytest (e.g. ./test.sh -m "not ros").
set -euo pipefail
cd "$(dirname "$0")"
source tools/ensure_env.sh
export ROS_LOG_DIR="${ROS_LOG_DIR:-$(mktemp -d)}"
rerun analytics disable >/dev/null 2>&1 || true
# Two workers (xdist): the ROS graph tests one after the other on one, the numerical tests beside
# them (groups by file, test/conftest.py); `./test.sh -n 0` runs everything in one process;
# `./test.sh -m fast` is the everyday tier (no ROS, no slow tests; docs/testing.md); the
# slowest 20 tests are listed at the end (the figures of docs/testing.md).
python -m pytest -q -n 2 --dist loadgroup --no-loadscope-reorder --durations=20 "$@"
