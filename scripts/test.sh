#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test. This is what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --peers   # peers too: the suite smoke test checks MRPT and OpenCV
bash scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)"
