#!/usr/bin/env bash
# Configures and builds cogmap in ./build (Release with debug info).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$(nproc)"
# `import cogmap` in Python from any folder: the build's module on the user's
# Python path (a .pth file in the user site folder; remove it to undo).
if compgen -G "build/python/cogmap*.so" >/dev/null; then
  py=/usr/bin/python3; [[ -x $py ]] || py=python3
  site=$("$py" -m site --user-site)
  mkdir -p "$site" && echo "$PWD/build/python" > "$site/cogmap-build.pth"
fi
