#!/bin/sh
# --cone-orientation (docs/walls.md, "A ring that looks only forward"): a
# ring that looks only forward takes its rooms' orientation from the cone
# grid, and report.json says which grid gave the walls kept and the
# orientation; a full ring keeps the axis grid's orientation, flag or not.
# On nine_rooms without noise, where every wall lies at 0 or 90 degrees,
# the rooms' orientations lean less from the cone grid.
#   tests/cone_orientation_test.sh COGMAP WORLD
set -eu
cogmap=$1 world=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for robot in pioneer8 pioneer16; do
  "$cogmap" simulate "$world" --robot "$robot" --noiseless -o "$work/$robot.log" > /dev/null
  "$cogmap" map "$work/$robot.log" --outputs geojson -o "$work/${robot}_axis" > /dev/null 2>&1
  "$cogmap" map "$work/$robot.log" --outputs geojson --cone-orientation -o "$work/${robot}_cone" > /dev/null 2>&1
done
python3 - "$work" <<'PY'
import json, math, statistics, sys
work = sys.argv[1]
def report(name):
    return json.load(open(f"{work}/{name}/report.json"))
def lean(r):  # median |grid direction|, modulo a quarter turn, over the ASRs with one
    d = [abs((a["heading_estimate"]["grid_direction_deg"] + 45.0) % 90.0 - 45.0)
         for a in r["asrs"] if a.get("heading_estimate") and a["heading_estimate"].get("grid_direction_deg") is not None]
    return statistics.median(d)
expect = {"pioneer8_axis": "axis", "pioneer8_cone": "cone", "pioneer16_axis": "axis", "pioneer16_cone": "axis"}
for name, grid in expect.items():
    g = report(name)["grids"]
    if g != {"walls_kept": "cone", "orientation": grid}:
        sys.exit(f"{name}: grids {g}, expected the orientation from the {grid} grid")
axis, cone = lean(report("pioneer8_axis")), lean(report("pioneer8_cone"))
print(f"pioneer8 rooms' lean, median: axis grid {axis:.2f} deg, cone grid {cone:.2f} deg")
if not cone < 0.7 * axis:
    sys.exit("the cone grid's orientation leans about as much as the axis grid's")
def estimates(r):
    return [a.get("heading_estimate") for a in r["asrs"]]
if estimates(report("pioneer16_axis")) != estimates(report("pioneer16_cone")):
    sys.exit("--cone-orientation changed a full ring's rooms")
PY
echo "ok"
