#!/bin/sh
# The drawing stack is loaded when a picture is first drawn (cogmap/draw/
# cairo_api.h). With one of its libraries unloadable (an empty file first on
# LD_LIBRARY_PATH): a map run that draws fails with one error naming the
# library, exit 1, its partial result set aside; one that draws nothing
# (--outputs geojson) succeeds.
#   tests/drawing_stack_test.sh COGMAP WORLD
set -eu
cogmap=$1 world=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$cogmap" simulate "$world" --max-time 40 --seed 2 -o "$work/run.log" > /dev/null
mkdir "$work/fake"
: > "$work/fake/libpango-1.0.so.0"
status=0
LD_LIBRARY_PATH="$work/fake" "$cogmap" map "$work/run.log" -o "$work/out" > /dev/null 2> "$work/err" || status=$?
[ "$status" -eq 1 ] || { echo "drawing run: exit $status, expected 1"; cat "$work/err"; exit 1; }
grep -q "^cogmap: error: cannot load the drawing library libpango-1.0.so.0: " "$work/err" ||
  { echo "drawing run: no error naming the library"; cat "$work/err"; exit 1; }
[ "$(grep -c '^cogmap: error' "$work/err")" -eq 1 ] || { echo "more than one error line"; cat "$work/err"; exit 1; }
ls "$work/out" | grep -q '^failed-run-' || { echo "partial result not set aside"; ls -a "$work/out"; exit 1; }
[ ! -e "$work/out/map.sqlite" ] || { echo "a failed run left map.sqlite"; exit 1; }
LD_LIBRARY_PATH="$work/fake" "$cogmap" map "$work/run.log" -o "$work/out2" --outputs geojson > /dev/null 2>&1 ||
  { echo "a run that draws nothing needed the drawing stack"; exit 1; }
[ -s "$work/out2/map.geojson" ] && [ -s "$work/out2/map.sqlite" ] || { echo "outputs missing"; exit 1; }
echo "ok"
