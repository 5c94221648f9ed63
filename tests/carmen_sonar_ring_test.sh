#!/bin/sh
# CARMEN logs as a Pioneer's 16-sonar ring (convert --as-sonar pioneer16,
# the ring fired as a Pioneer fires it), mapped against their reference
# poses:
# - intel at 1 deg/m: the drift is found and taken out (heading median
#   within 0.5 degrees). With the ring fired at the laser's scans alone,
#   once every 0.62 m, 65 of 118 rooms had no wall and the map stayed at
#   its odometry's 65 degrees.
# - fhw (a museum, walls at many angles) without drift: no drift is found
#   (first measured with the ring reading the scans either side only).
#   The drift test solved the model without drift from the drift's own
#   solution and stopped in a basin far worse than the odometry's: a drift
#   of 2.26 deg/m was kept, ATE 35.7 m against the exact input.
# - fhw at 1 deg/m: the drift is found (its own solve stopped near no drift;
#   the scan of the rates finds it) and the map is far better than its
#   odometry.
# - belgioioso without drift (below).
# Every run: a wing's warning names the wing the map keeps.
#   tests/carmen_sonar_ring_test.sh COGMAP SHARED
set -eu
cogmap=$1
shared=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run() {  # log drift [convert options]
  log=$1 drift=$2
  shift 2
  [ -f "$work/$log.log" ] || "$cogmap" convert "$shared/data/carmen/$log-corrected.log.gz" --as-sonar pioneer16 "$@" \
    -o "$work/$log.log" > /dev/null 2>&1
  set -- "$log" "$drift"
  "$cogmap" map "$work/$1.log" --add-drift-deg-per-m "$2" --outputs geojson -o "$work/$1_$2" > "$work/$1_$2.txt" 2>&1 ||
    { cat "$work/$1_$2.txt"; exit 1; }
  "$cogmap" eval "$work/$1_$2" --json > "$work/$1_$2.json"
}
check() {  # log drift what
  python3 - "$1" "$2" "$3" "$work/$1_$2.json" "$work/$1_$2/report.json" <<'PY'
import json, re, sys
log, drift, what = sys.argv[1], float(sys.argv[2]), sys.argv[3]
e, g = json.load(open(sys.argv[4])), json.load(open(sys.argv[5]))["pose_graph"]
print(f"{log} at {drift:g} deg/m: drift {g['drift_rate_deg_per_m']:.3f} (found: {g['drift_detected']}), heading median "
      f"{e['heading_error_deg_median']:.2f} deg (odometry {e['heading_error_deg_median_raw']:.2f}), ATE "
      f"{e['ate_rmse_m']:.3f} m (odometry {e['ate_rmse_m_raw']:.3f})")
if what == "corrected":
    if not g["drift_detected"] or abs(g["drift_rate_deg_per_m"] - drift) > 0.3:
        sys.exit(f"{log}: the drift of {drift} deg/m was not found")
    if e["ate_rmse_m"] > 0.1 * e["ate_rmse_m_raw"]:
        sys.exit(f"{log}: the map is not far better than its odometry")
if what == "heading" and e["heading_error_deg_median"] > 0.5:
    sys.exit(f"{log}: heading median over 0.5 degrees")
# A wing's warning names the wing the map keeps (report.json's building
# directions), or says that its directions drew together when solved.
dirs = g.get("building_directions_deg") or []
gaps = [abs((a - b + 45.0) % 90.0 - 45.0) for i, a in enumerate(dirs) for b in dirs[:i]]
for w in g.get("warnings", []):
    m = re.search(r"a wing turned (\d+) degrees against the rest is kept", w)
    if m and abs(int(m.group(1)) - max(gaps)) > 0.5:
        sys.exit(f"{log}: the warning names a {m.group(1)}-degree wing, the map keeps {max(gaps):.1f}: {w}")
    m = re.search(r"drew to ([\d.]+) degrees apart", w)
    if m and "kept under the test's margin" in w and abs(float(m.group(1)) - min(gaps)) > 0.06:
        sys.exit(f"{log}: the warning says {m.group(1)} degrees apart, the map keeps {min(gaps):.2f}: {w}")
if what == "nodrift":
    if g["drift_detected"]:
        sys.exit(f"{log}: a drift was found where there is none")
    if e["ate_rmse_m"] > 1.5:
        sys.exit(f"{log}: the map moved more than 1 m (ATE) from its exact input")
PY
}
run intel 1 && check intel 1 corrected && check intel 1 heading
run fhw 0 && check fhw 0 nodrift
run fhw 1 && check fhw 1 corrected
# belgioioso without drift, as converted by default: a wing kept under the
# test's margin drew to 2.2 degrees apart when solved with the whole map,
# while its warning named the 35.7 degrees it had been found at (check
# above, for every run).
run belgioioso 0 && check belgioioso 0 nodrift
mv "$work/belgioioso.log" "$work/belgioioso_default.log"
# belgioioso, the ring reading the scans either side only, no drift: the
# drift test's nested model, solved from the drift's solution alone, left
# the map turned (heading median 16 degrees, ATE 13.3 m); now 0.84 m.
mv "$work/fhw.log" "$work/fhw_default.log"
run belgioioso 0 --ring-history-m 0 && check belgioioso 0 nodrift
echo "ok"
