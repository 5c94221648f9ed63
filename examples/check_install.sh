#!/usr/bin/env bash
# The installed package as another project sees it (ctest: install_package):
# `cmake --install` into a fresh prefix, examples/map_a_log configured and built
# against it with find_package(cogmap), run on a simulated log, and its ASR and
# room counts compared with the installed `cogmap map` on the same log; then
# `cpack -G DEB` and the package's contents.
#   check_install.sh BUILD_DIR SOURCE_DIR SHARED_DIR
set -euo pipefail
build=$(cd "$1" && pwd); src=$(cd "$2" && pwd); shared=$(cd "$3" && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" --strip >/dev/null
test -x "$prefix/bin/cogmap"
test -f "$prefix/lib/cmake/cogmap/cogmapConfig.cmake" || test -f "$prefix"/lib/*/cmake/cogmap/cogmapConfig.cmake
test -f "$prefix/include/cogmap/mapping/pipeline.h"
if grep -rlE "CLI/|CLI11" "$prefix/include/cogmap"; then echo "public headers include CLI11" >&2; exit 1; fi

cmake -S "$src/examples/map_a_log" -B "$work/example" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/example" >/dev/null

"$prefix/bin/cogmap" simulate "$shared/worlds/nine_rooms.map" --seed 2 --drift-deg-per-m 1 -o "$work/run.log" >/dev/null
"$work/example/map_a_log" "$work/run.log" "$work/api.sqlite" > "$work/api.txt"
"$prefix/bin/cogmap" map "$work/run.log" -o "$work/cmd" >/dev/null
api=$(tail -1 "$work/api.txt")
cmd=$(python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print('asrs %d rooms %d closures %d records %d' % (r['asr_count'], r['pose_graph']['rooms'], r['pose_graph']['closures_accepted'], r['records']))" "$work/cmd/report.json")
echo "example: $api"
echo "command: $cmd"
[[ "$api" == "$cmd" ]] || { echo "the example consumer and the command disagree" >&2; exit 1; }
closed=$(grep -c "^ASR .* closed" "$work/api.txt")
[[ "$closed" == "$(echo "$api" | awk '{print $2}')" ]]

# The Debian package of the same install.
(cd "$build" && cpack -G DEB -B "$work/deb" >/dev/null)
deb=$(ls "$work"/deb/cogmap_*.deb)
contents=$(dpkg-deb -c "$deb"); info=$(dpkg-deb -I "$deb")
grep -q "usr/bin/cogmap$" <<<"$contents"
grep -q "cogmapConfig.cmake$" <<<"$contents"
grep -q "Package: cogmap" <<<"$info"
# Stripped (CPACK_STRIP_FILES): no debug sections in the packaged command.
dpkg-deb -x "$deb" "$work/unpacked"
if readelf -S "$work/unpacked/usr/bin/cogmap" | grep -q "\.debug_info"; then
  echo "the packaged cogmap keeps its debug info" >&2; exit 1
fi
echo "package: $(basename "$deb") $(du -k "$deb" | cut -f1) KiB"
