#!/bin/sh
# A log whose timestamps do not advance (CARMEN's belgioioso writes them to
# six digits: every record at 1.01893e+09 s) has no x real time: report.json
# says null and the terminal says why, instead of "0.0x real time".
#   tests/frozen_clock_test.sh COGMAP SHARED_DIR
set -eu
cogmap=$1 shared=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cogmap" map "$shared/data/carmen/belgioioso-corrected.log.gz" --outputs geojson -o "$work/out" > "$work/stdout" 2> /dev/null
grep -q "x real time unknown: the log's timestamps do not advance" "$work/stdout"
python3 - "$work/out/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ok = r["log_duration_s"] == 0 and r["times_real_time"] is None and r["mapping_times_real_time"] is None
sys.exit(0 if ok else 1)
PY
echo "ok"
