#!/bin/sh
# Spaces cut by distance (`cogmap map --max-asr`): the floor plan joins the
# pieces of one room again (an exit of no measured width parts nothing,
# plan/plan.cc "Spaces cut by distance"), and the pose graph does not take
# a piece of the room next door for a revisit (graph::SameSpace). nine_rooms,
# laser, every space cut after 8 m: before these, room IoU median 0.37 and
# 45 wrong revisits over the bench's runs (this one: 9).
#   tests/cut_by_distance_test.sh COGMAP WORLD
set -eu
cogmap=$1 world=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cogmap" simulate "$world" --robot laser --seed 1 -o "$work/run.log" > /dev/null
"$cogmap" map "$work/run.log" --max-asr 8 --outputs geojson -o "$work/out" > /dev/null 2>&1
"$cogmap" eval "$work/out" --world "$world" --json > "$work/eval.json"
python3 - "$work/eval.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"ASRs {j['asr_count']}, plan rooms {j['plan_rooms']}, room IoU median {j['room_iou_median']:.3f}, "
      f"revisits {j['revisits']} (wrong {j['revisits_wrong']})")
ok = j["revisits_wrong"] == 0 and j["room_iou_median"] >= 0.8 and j["asr_count"] > 9
sys.exit(0 if ok else 1)
PY
echo "ok"
