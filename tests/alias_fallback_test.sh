#!/bin/sh
# The real CARMEN log fhw with 1 deg/m of heading drift added and its spaces
# cut every 8 m. Nineteenth session: the wall directions carried the run
# along a quarter-turn alias of its drift (turned 837 degrees, ATE 56.5 m
# against the odometry's 34.8), and the alias check sent it back to its
# odometry (graph::MapOptimizerOptions::max_turn_without_drift_rad).
# Twentieth session: the alias came from short ASRs whose two or three wall
# edges claimed their direction to a degree or two (localize::RobustEmOptions
# small_sample_correction); read for what few edges can tell, the drift is
# found (about 1 deg/m) and the run corrected. Either way the run must end
# no worse than its odometry, and a run left at its odometry must say why.
#   tests/alias_fallback_test.sh COGMAP SHARED_DIR
set -eu
cogmap=$1 shared=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cogmap" map "$shared/data/carmen/fhw-corrected.log.gz" --add-drift-deg-per-m 1 --max-asr 8 \
  --outputs geojson -o "$work/out" > /dev/null 2> "$work/err"
"$cogmap" eval "$work/out" --json > "$work/eval.json"
python3 - "$work/eval.json" "$work/out/report.json" "$work/err" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
pg = json.load(open(sys.argv[2]))["pose_graph"]
err = open(sys.argv[3]).read()
ate, raw = j["ate_rmse_m"], j["ate_rmse_m_raw"]
print(f"ATE {ate:.3f} m, odometry {raw:.3f} m, solution {pg['solution']}, drift {pg['drift_rate_deg_per_m']:.2f} deg/m")
if ate > 1.05 * raw + 0.02:
    sys.exit("worse than the odometry")
if pg["solution"] == "odometry" and "using the odometry" not in err:
    sys.exit("left at the odometry without a warning")
if pg["drift_detected"] and not (0.7 <= pg["drift_rate_deg_per_m"] <= 1.3 and ate < 0.1 * raw):
    sys.exit("a drift found, but not the one added")
PY
echo "ok"
