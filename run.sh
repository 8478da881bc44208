#!/usr/bin/env bash
# The main job of the README: installs what it needs on first use (.venv), then runs the most
# complete campaign the tool has. Extra arguments go to the motoflex verb.
set -euo pipefail
cd "$(dirname "$0")"
source tools/ensure_env.sh
export ROS_LOG_DIR="${ROS_LOG_DIR:-$(mktemp -d)}"
exec motoflex campaign "$@"
