#!/usr/bin/env bash
# The main job: installs what is missing, builds, then maps a bundled world
# end to end and writes every output into out/demo/ (or the folder given).
#   1. simulates a Pioneer 3-DX with its 16-sonar ring driving nine_rooms.map
#      with 1 degree/metre of heading drift (the thesis's test environment);
#   2. draws the world with the true and the odometry paths;
#   3. builds the cognitive map (ASRs, exits, the pose graph) and its floor
#      plan with all their outputs: map.sqlite, map.svg/.png (every ASR),
#      plan.json and plan.svg/.png (the floor plan), map.gpkg, map.geojson,
#      route_graph.geojson (Nav2), map.map (ARIA 2D-Map), map.pgm/.yaml,
#      map_compare.svg/.png (before | after the pose correction),
#      heading_error.png, walls.json, report.json;
#   4. scores it against the floor plan (cogmap eval);
#   5. also vectorizes the whole run as one space (stages.png) and draws the
#      grid of the real Pioneer sonar log.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/demo}
SHARED=${COGMAP_SHARED_DIR:-$(cd .. && pwd)/shared}
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p "$OUT"
C=build/app/cogmap
WORLD="$SHARED/worlds/nine_rooms.map"

echo "== simulate nine_rooms (pioneer16, 1 deg/m drift, seed 1)"
$C simulate "$WORLD" --robot pioneer16 --route --seed 1 --drift-deg-per-m 1.0 -o "$OUT/nine_rooms.log"
$C render-world "$WORLD" --log "$OUT/nine_rooms.log" -o "$OUT/world.png"

echo "== cognitive map"
$C map "$OUT/nine_rooms.log" -o "$OUT/map" --outputs all
$C eval "$OUT/map" --world "$WORLD" | tee "$OUT/eval.txt"

echo "== whole run as one space (stages of SPEC 3)"
$C vectorize "$OUT/nine_rooms.log" -o "$OUT/vectorize"

echo "== grid of the real Pioneer sonar log"
$C grid "$SHARED/data/pioneer-sonar-robond" -o "$OUT/pioneer-grid.png" --pgm "$OUT/pioneer-grid"

echo
echo "outputs in $OUT:"
ls -1 "$OUT" "$OUT/map"
