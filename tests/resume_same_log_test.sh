#!/bin/sh
# `cogmap map LOG --resume` given the log the store was mapped from
# (thirty-second session). The store keeps the log's fingerprint and how
# many of its records the run had read when its last ASR closed; such a
# resume continues from there instead of mapping the log a second time
# (which stacked every room twice). Checked here:
#   1. a finished map resumed with its own log: exit 2, "nothing to resume",
#      every file of the folder as it was, no failed-run folder;
#   2. a store whose run was killed after its last room closed (emulated:
#      no placements, finished_through -1, no world_from_map): resumed with
#      its log, the run is finished and the map equals the uninterrupted one;
#   3. a store of another log resumed with this one: mapped from its start;
#   4. a folder holding only a killed run's store (set aside as
#      failed-run-*-killed): --resume says where it is and how to continue it;
#   5. a store whose log identity is damaged: exit 2, the folder untouched.
#   6. a store whose finished_through, next_asr_id, last_raw_pose or
#      world_from_map is not what a run writes: exit 2 naming the store and
#      the key, the folder untouched.
# (tests/kill_test.py resumes killed runs mid-log with the whole log.)
#   tests/resume_same_log_test.sh COGMAP SHARED_DIR
set -eu
cogmap=$1 shared=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
world="$shared/worlds/nine_rooms.map"
"$cogmap" simulate "$world" --seed 3 -o "$work/run.log" > /dev/null
"$cogmap" simulate "$world" --seed 4 -o "$work/other.log" > /dev/null
"$cogmap" map "$work/run.log" --world "$world" -o "$work/out" > /dev/null 2>&1

# `cogmap map run.log --resume -o DIR` must exit 2 with PATTERN in its
# message and leave every file of DIR as it was, with no failed-run folder.
refused() {
  dir=$1 pattern=$2
  (cd "$dir" && sha256sum $(ls) > "$work/before.sha")
  if "$cogmap" map "$work/run.log" --resume -o "$dir" > /dev/null 2> "$work/err"; then
    echo "$dir: the resume succeeded"; exit 1
  else
    status=$?
  fi
  test "$status" -eq 2 || { echo "$dir: exit $status, expected 2"; exit 1; }
  grep -q "$pattern" "$work/err" || { cat "$work/err"; exit 1; }
  (cd "$dir" && sha256sum -c --quiet "$work/before.sha") || { echo "$dir: the folder changed"; exit 1; }
  if ls -d "$dir"/failed-run-* > /dev/null 2>&1; then echo "$dir: a failed-run folder was left"; exit 1; fi
}

# 1. Nothing new: refused, the folder untouched.
refused "$work/out" "nothing to resume"

# 2. A run killed after its last room closed, resumed with its log: finished.
mkdir "$work/killed"
cp "$work/out/map.sqlite" "$work/killed/"
python3 - "$work/killed/map.sqlite" <<'PY'
import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
db.execute("UPDATE meta SET value = '-1' WHERE key = 'finished_through'")
db.execute("DELETE FROM placement")
db.execute("DELETE FROM meta WHERE key = 'world_from_map'")
db.commit()
PY
"$cogmap" map "$work/run.log" --world "$world" --resume -o "$work/killed" > /dev/null 2> "$work/err2"
grep -q "finishing the run that was cut short" "$work/err2" || { cat "$work/err2"; exit 1; }
"$cogmap" eval "$work/out" --world "$world" --json > "$work/full.json"
"$cogmap" eval "$work/killed" --world "$world" --json > "$work/resumed.json"

# 3. Another log's store: this log is new to it, mapped from its first record.
"$cogmap" map "$work/other.log" -o "$work/two" > /dev/null 2>&1
"$cogmap" map "$work/run.log" --resume -o "$work/two" > /dev/null 2>&1

# 4. A folder whose only store is a killed run's, set aside: --resume says where.
mkdir -p "$work/fresh/failed-run-20260101-000000-1-killed"
cp "$work/out/map.sqlite" "$work/fresh/failed-run-20260101-000000-1-killed/"
if "$cogmap" map "$work/run.log" --resume -o "$work/fresh" > /dev/null 2> "$work/err4"; then
  echo "resuming a folder without a store succeeded"; exit 1
fi
grep -q "a killed run's store is in .*failed-run-20260101-000000-1-killed/: continue it with -o" "$work/err4" ||
  { cat "$work/err4"; exit 1; }

# 5. A store whose log identity no run wrote (last_record 'abc'): exit 2
#    naming the store, the folder as it was (not the log mapped a second time).
cp -r "$work/out" "$work/damaged"
python3 -c "import sqlite3, sys; db = sqlite3.connect(sys.argv[1]); db.execute(\"UPDATE meta SET value = 'abc' WHERE key = 'last_record'\"); db.commit()" "$work/damaged/map.sqlite"
refused "$work/damaged" "damaged/map.sqlite: a damaged store"

# 6. Meta values a run reads back to continue (finished_through, next_asr_id,
#    last_raw_pose) that are not what a run writes: exit 2 naming the store
#    and the key, the folder as it was (they were read with atoi: 'x' was 0).
for bad in "finished_through|x12" "next_asr_id|99999999999999999999" "next_asr_id|-5" "last_raw_pose|1 2 nan" \
           "last_raw_pose|1 2" "world_from_map|0 0 zero"; do
  key=${bad%%|*} value=${bad#*|}
  rm -rf "$work/meta"
  cp -r "$work/out" "$work/meta"
  python3 -c "import sqlite3, sys; db = sqlite3.connect(sys.argv[1]); db.execute('UPDATE meta SET value = ? WHERE key = ?', (sys.argv[3], sys.argv[2])); db.commit(); assert db.total_changes == 1" \
    "$work/meta/map.sqlite" "$key" "$value"
  refused "$work/meta" "meta/map.sqlite: a damaged store: meta $key is"
done

python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
full, res = json.load(open(w + "/full.json")), json.load(open(w + "/resumed.json"))
rep = json.load(open(w + "/killed/report.json"))
two = json.load(open(w + "/two/report.json"))
print(f"finished from the store: {res['asr_count']} ASRs (uninterrupted {full['asr_count']}), "
      f"wall p95 {res['wall_precision_p95_m']:.3f} m ({full['wall_precision_p95_m']:.3f}), "
      f"ATE {res['ate_rmse_m']:.3f} m ({full['ate_rmse_m']:.3f}), {rep['replayed_asrs']} ASRs placed again; "
      f"another log's store: {two['asr_count_this_run']} new ASRs, resumed after record {two['resumed_after_record']}")
if rep["resumed_after_record"] <= 0 or rep["records"] != 0:
    sys.exit("the killed store's run was not taken up where it stopped")
for k in ("asr_count", "wall_precision_p95_m", "wall_recall", "ate_rmse_m", "room_iou_median"):
    if abs(full[k] - res[k]) > 1e-6:
        sys.exit(f"{k}: {res[k]} against the uninterrupted run's {full[k]}")
if two["resumed_after_record"] != 0 or two["asr_count_this_run"] < 5:
    sys.exit("another log's store: this log was not mapped from its start")
PY
echo "ok"
