#!/usr/bin/env bash
# Rebuilds the shipped rawlogs (rawlog + ground truth + sidecar ini) from the project's gzipped
# copies of the public datasets in data/datasets (see data/README.md) and the scenario simulator;
# the sidecars of the rawlogs named in data/minimization get those settings appended.
#   tools/make_rawlogs.sh [OUT_DIR]      default OUT_DIR: rawlogs/
# Binaries are taken from $BUDGET_SLAM_BIN (default: build/bin). The kf-slam demo files in
# rawlogs/ are copies of MRPT's and are not rebuilt here.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$(realpath -m "${1:-$root/rawlogs}")"
bin="$(realpath -m "${BUDGET_SLAM_BIN:-$root/build/bin}")"
for tool in budget-convert budget-simulate; do
  if [[ ! -x "$bin/$tool" ]]; then
    echo "make_rawlogs.sh: $bin/$tool not found (build first, or set BUDGET_SLAM_BIN)" >&2
    exit 1
  fi
done
mkdir -p "$out"
cd "$root"
data=data/datasets

"$bin/budget-convert" --format isam "$data/victoria_park_gtsam/victoria_park.txt" \
  -o "$out/victoria_park.rawlog"
"$bin/budget-convert" --format utias "$data/utias_mrclam/MRCLAM_Dataset7" --robot 1 \
  -o "$out/mrclam7_robot1.rawlog"
"$bin/budget-simulate" --scenario rooms --seed 1 -o "$out/rooms.rawlog"
"$bin/budget-simulate" --scenario paper-synthetic --seed 1 -o "$out/paper_synthetic.rawlog"
"$bin/budget-simulate" --scenario park --seed 1 -o "$out/park.rawlog"
"$bin/budget-simulate" --scenario corridors --seed 1 -o "$out/corridors.rawlog"
"$bin/budget-simulate" --scenario clusters --seed 1 -o "$out/clusters.rawlog"

# Second traversals to relocalize on (budget-slam localize, compare --relocalize): the same worlds
# along other routes with other noise; MRCLAM robots 2-5 in robot 1's world frame; Victoria Park
# from step 3500 on (map with max_steps = 3500 on victoria_park.rawlog).
"$bin/budget-simulate" --scenario rooms --seed 1 --route revisit -o "$out/rooms_revisit.rawlog"
"$bin/budget-simulate" --scenario park --seed 1 --route revisit -o "$out/park_revisit.rawlog"
"$bin/budget-simulate" --scenario corridors --seed 1 --route revisit -o "$out/corridors_revisit.rawlog"
"$bin/budget-simulate" --scenario clusters --seed 1 --route revisit -o "$out/clusters_revisit.rawlog"
for robot in 2 3 4 5; do
  "$bin/budget-convert" --format utias "$data/utias_mrclam/MRCLAM_Dataset7" --robot "$robot" \
    --frame-robot 1 -o "$out/mrclam7_robot$robot.rawlog"
done
"$bin/budget-convert" --format isam "$data/victoria_park_gtsam/victoria_park.txt" --steps 3500: \
  -o "$out/victoria_park_from3500.rawlog"

# Per-rawlog reduced-landmark SLAM settings (the paper's psi; lambda / stop calibrated to its
# reductions, docs/ALGORITHMS.md "Calibration") go after the sensor noise in the sidecar.
for settings in data/minimization/*.ini; do
  cat "$settings" >> "$out/$(basename "$settings")"
done
