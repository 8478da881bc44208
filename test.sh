#!/usr/bin/env bash
# The test command of the README: installs what it needs on first use (.venv), then runs the
# linter and the whole test suite. Extra arguments go to pytest (e.g. ./test.sh -m "not ros").
set -euo pipefail
cd "$(dirname "$0")"
source tools/ensure_env.sh
export ROS_LOG_DIR="${ROS_LOG_DIR:-$(mktemp -d)}"
rerun analytics disable >/dev/null 2>&1 || true
python -m pytest -q "$@"
