#!/bin/sh
# Without drift, the odometry's heading is its model's random walk. Eight
# sonars on a generated building whose second wing is turned 45 degrees
# (bench/never_worse --random 40 --random-seed 40: rand40-4) read the
# wing's walls as the building's: the variance components took the
# odometry's heading for 10 times noisier than its model, and the walls
# turned the map (ATE 2.30 m against the odometry's 0.20, wall p95 3.35 m
# against 0.50). The fit is tried again with the odometry's heading held at
# its model (graph::MapOptimizerOptions::heading_model_test_probability):
# the map must say so in report.json and end no worse than its odometry
# (both its walls and its trajectory worse, as bench/never_worse counts it).
# Since the room next door weighs each closure (fifty-ninth session),
# rand40-4 keeps none of the wrong closures that inflated the fit (2.9
# times its model, not held; ATE 0.09 m, the odometry's 0.20): the case is
# now rand49-39 (--random-seed 49), eight sonars on a 35-degree wing, whose
# walls still fit the odometry's heading 4.8 times as noisy.
#   tests/heading_model_test.sh COGMAP
set -eu
cogmap=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cogmap" gen-building --rooms 24 --corridor-m 25 --corridor-width-m 3.0 --room-depth-m 8.0 --door-m 0.8 \
  --wing-deg -35 --seed 41 -o "$work/building.map" > /dev/null
"$cogmap" simulate "$work/building.map" --robot pioneer8 --drift-deg-per-m 0 --seed 11 --max-time 900 \
  -o "$work/run.log" > /dev/null
"$cogmap" map "$work/run.log" --outputs geojson -o "$work/graph" > "$work/summary.txt" 2>&1
grep -q "^odometry heading: held at its motion model (the walls fitted it [0-9.]* times" "$work/summary.txt" ||
  { cat "$work/summary.txt"; echo "the summary does not say the odometry's heading was held"; exit 1; }
"$cogmap" map "$work/run.log" --no-correct --outputs geojson -o "$work/odometry" > /dev/null 2>&1
"$cogmap" eval "$work/graph" --world "$work/building.map" --json > "$work/graph.json"
"$cogmap" eval "$work/odometry" --world "$work/building.map" --json > "$work/odometry.json"
python3 - "$work/graph.json" "$work/odometry.json" "$work/graph/report.json" <<'PY'
import json, sys
g, o = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
pg = json.load(open(sys.argv[3]))["pose_graph"]
fitted = pg["odometry_heading_fitted_factor"]
print(f"ATE {g['ate_rmse_m']:.3f} m (odometry {o['ate_rmse_m']:.3f}), wall p95 {g['wall_precision_p95_m']:.3f} m "
      f"(odometry {o['wall_precision_p95_m']:.3f}); heading factor fitted {fitted}, held {pg['odometry_heading_held']}")
if fitted is None or fitted < 3.0 or not pg["odometry_heading_held"]:
    sys.exit("the odometry's heading was not held at its model (the case is not the one it claims to be)")
if pg["sigma_factors"]["odometry_heading"] != 1.0:
    sys.exit("held, but its factor is not the model's")
# Worse as bench/never_worse counts it: both the walls and the trajectory.
if all(g[key] > 1.05 * o[key] + 0.02 for key in ("ate_rmse_m", "wall_precision_p95_m")):
    sys.exit("worse than the odometry")
PY
echo "ok"
