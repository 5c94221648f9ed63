#!/usr/bin/env bash
# Installs every Debian package cogmap needs to build, test and benchmark.
# Safe to run again: it installs only what is missing.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libcli11-dev nlohmann-json3-dev libpng-dev zlib1g-dev libsqlite3-dev
  libgtest-dev libgmock-dev libbenchmark-dev libceres-dev ccache
  # Boost.Geometry (header only): the floor plan's polygon clipping
  libboost-dev
  # ROS 1 bags (cogmap/io/ros1_bag*): rosbag_storage and the message headers
  librosbag-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev libgeometry-msgs-dev libstd-msgs-dev
  # MRPT rawlogs (cogmap/io/mrpt_rawlog*)
  libmrpt-dev
  python3
  time  # GNU time: the bench measures each command's own peak memory through it (bench/suite/peak_rss.py)
  gdal-bin  # ogrinfo: tests read map.gpkg and map.geojson back with GDAL
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3-matplotlib  # the Python docs' example, run by the pytest suite
  # the live ROS 1 node (ros/) and its test against a real roscore
  libroscpp-dev libstd-srvs-dev libvisualization-msgs-dev ros-core python3-rospy python3-rosbag
  python3-rosservice python3-rostopic python3-visualization-msgs python3-nav-msgs python3-std-srvs
  libcairo2-dev libpango1.0-dev fonts-dejavu-core chromium
)
# Peers for side-by-side comparisons (bench/), large: only with --peers.
# clang with libFuzzer and the sanitizer runtimes (scripts/fuzz.sh): only with --fuzz.
for opt in "$@"; do
  case "$opt" in
    --peers) PKGS+=(libopencv-dev mrpt-apps) ;;
    --fuzz) PKGS+=(clang libclang-rt-14-dev) ;;
    *) echo "install-deps.sh: unknown option $opt (--peers, --fuzz)" >&2; exit 2 ;;
  esac
done
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""
  [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  echo "installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
