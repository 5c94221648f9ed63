#!/usr/bin/env bash
# End to end (issue 11): a generated 100-room building, simulated, mapped and
# scored; the floor plan's rooms must not overlap (room_overlap_m2 = 0, as
# `cogmap eval` measures it) and the plan must have rooms. Before the rooms
# were made from disjoint half-cell sets, this building's plan had 0.19 m^2
# of overlap. Usage: plan_overlap_e2e_test.sh COGMAP WORKDIR
set -euo pipefail
cogmap=$1
dir=$2/plan_overlap_e2e
rm -rf "$dir"
mkdir -p "$dir"
"$cogmap" gen-building --rooms 100 --corridor-m 400 --seed 1 -o "$dir/building.map" > /dev/null
"$cogmap" simulate "$dir/building.map" --robot pioneer16 --seed 1 --drift-deg-per-m 0 -o "$dir/run.log" > /dev/null
"$cogmap" map "$dir/run.log" --outputs plan -o "$dir/map" > /dev/null 2>&1
"$cogmap" eval "$dir/map" --world "$dir/building.map" --json > "$dir/eval.json"
overlap=$(sed -n 's/.*"room_overlap_m2": *\([^,]*\),*/\1/p' "$dir/eval.json")
rooms=$(sed -n 's/.*"plan_rooms": *\([^,]*\),*/\1/p' "$dir/eval.json")
echo "plan_rooms $rooms room_overlap_m2 $overlap"
[[ -n "$overlap" && -n "$rooms" ]] || { echo "eval printed no room_overlap_m2 / plan_rooms"; exit 1; }
awk -v o="$overlap" -v r="$rooms" 'BEGIN { exit !(o == 0 && r >= 50) }' || { echo "FAIL: overlap $overlap m^2, $rooms rooms"; exit 1; }
rm -rf "$dir"
