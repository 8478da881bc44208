#!/usr/bin/env bash
# Install Debian's chromium for the browser test of the rerun web viewer (test/test_view_browser.py).
# Cached: does nothing when /usr/bin/chromium exists. Needs root (CI runs as root) and apt-get.
# Exit codes: 0 installed or already present, 3 apt-get not available, 4 not root.
set -euo pipefail
if [ -x /usr/bin/chromium ]; then
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "install_chromium: apt-get not available; cannot install chromium" >&2
    exit 3
fi
if [ "$(id -u)" != "0" ]; then
    echo "install_chromium: must run as root to install chromium with apt-get" >&2
    exit 4
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >/dev/null
/usr/bin/chromium --version
