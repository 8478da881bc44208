#!/usr/bin/env bash
# Create (first use) or reuse (later uses) the project's virtual environment in .venv.
# Re-installs only when setup.py or this script changed (stamp = hash of both).
# Sourced by run.sh and test.sh; needs only python3 (3.10-3.12) and the package registries.
# Leaves the caller's shell options as they were (the installation runs in a subshell with
# errexit); returns non-zero when it fails.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
STAMP="$VENV/.motoflex-stamp"
want="$(cat "$ROOT/setup.py" "$ROOT/tools/ensure_env.sh" | sha256sum | cut -c1-16)"
if [ ! -f "$STAMP" ] || [ "$(cat "$STAMP")" != "$want" ]; then
  ( set -euo pipefail
    echo "motoflex: preparing the environment in .venv (first use takes about two minutes)" >&2
    PY="${PYTHON:-python3}"
    [ -x "$VENV/bin/python" ] || "$PY" -m venv "$VENV"
    [ -x "$VENV/bin/uv" ] || "$VENV/bin/python" -m pip install --quiet uv
    # uv reads no pip configuration: it resolves from the public index only. --compile-bytecode:
    # uv writes no .pyc by default, and every node process of a campaign would compile scipy
    # from source again (about 1.4 CPU-s each; worst with PYTHONDONTWRITEBYTECODE set).
    "$VENV/bin/uv" pip install --quiet --compile-bytecode --python "$VENV/bin/python" \
        -e "$ROOT[ros,record,scale,test]"
    echo "$want" > "$STAMP"
  ) || { echo "motoflex: preparing .venv failed (see above)" >&2; return 1 2>/dev/null || exit 1; }
fi
export PATH="$VENV/bin:$PATH"
export ROS_AUTOMATIC_DISCOVERY_RANGE="${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}"
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
export MPLBACKEND="${MPLBACKEND:-Agg}"
