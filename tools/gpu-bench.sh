#!/usr/bin/env bash
# Measures fur on a real GPU: the tables docs/benchmark.md has only for lavapipe so far.
# Run it from the repository root on a machine with a desktop GPU (Vulkan 1.3 with
# tessellation and geometry shaders):
#
#   bash tools/gpu-bench.sh            # the default device (discrete > integrated > cpu)
#   bash tools/gpu-bench.sh 1          # device 1 of `fur devices`
#   bash tools/gpu-bench.sh rtx        # the one usable device whose name contains "rtx"
#   bash tools/gpu-bench.sh "" --quick # further arguments go to both `fur bench` runs
#
# It builds the release binary, lists the devices, then runs
#   1. `fur bench`: every section (frame times, quality, simulation, collision, looks,
#      ladder, animation) into bench-<device>/;
#   2. the goal's scene (assets/scenes/goal.toml: 19,901 simulated masters, ~500K drawn
#      hairs) in the frame section at 1920x1080 into bench-<device>/goal/: the goal is
#      a frame under 2 ms (the "GPU ms" column).
# Each folder gets results.md (the tables), results.csv (every measurement) and charts.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
choice="${1:-}"
shift || true

cargo build --release --locked
fur=target/release/fur

device_args=()
if [[ -n "$choice" ]]; then
    device_args=(--device "$choice")
fi

# The list, with the device this run uses marked `*` (a bad choice stops here, with
# the list).
listing="$("$fur" devices ${device_args[@]+"${device_args[@]}"})"
echo "$listing"
# Columns are separated by two or more spaces: mark and index, type, Vulkan, name, ...
name="$(awk -F '  +' '/^\* / { print $4; exit }' <<<"$listing")"
kind="$(awk -F '  +' '/^\* / { print $2; exit }' <<<"$listing")"
if [[ -z "$name" ]]; then
    echo "no usable device is marked above; nothing to measure" >&2
    exit 1
fi
if [[ "$kind" == cpu ]]; then
    echo "warning: $name is a CPU driver: the full suite takes hours there, and the" >&2
    echo "goal's scene seconds a frame; choose a GPU with: bash tools/gpu-bench.sh INDEX" >&2
fi
slug="$(tr '[:upper:]' '[:lower:]' <<<"$name" | tr -cs 'a-z0-9' '-' | sed 's/^-*//; s/-*$//' | cut -c1-48)"
out="bench-${slug:-gpu}"
echo
echo "measuring $name into $out/"

"$fur" bench ${device_args[@]+"${device_args[@]}"} --out-dir "$out" "$@"
"$fur" bench ${device_args[@]+"${device_args[@]}"} --only frame --scene assets/scenes/goal.toml \
    --width 1920 --height 1080 --out-dir "$out/goal" "$@"

echo
echo "The tables for $name:"
echo "  $out/results.md       the full suite (results.csv: every measurement; *.svg: charts)"
echo "  $out/goal/results.md  the goal: 20K simulated masters, 500K drawn hairs at 1920x1080"
echo "Send both folders, or paste the tables under \"On a desktop GPU\" in docs/benchmark.md."
