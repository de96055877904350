#!/usr/bin/env bash
# Measures fur on a real GPU: every `fur bench` section, the performance goal's frame,
# and what bounds that frame. Run it from the repository root on a machine with a GPU
# (Vulkan 1.3 with tessellation and geometry shaders):
#
#   bash tools/gpu-bench.sh            # the default device (discrete > integrated > cpu)
#   bash tools/gpu-bench.sh 1          # device 1 of `fur devices`
#   bash tools/gpu-bench.sh rtx        # the one usable device whose name contains "rtx"
#   bash tools/gpu-bench.sh --quick    # further arguments go to every `fur bench` run
#
# It builds the release binary (or, where there is no cargo, uses target/release/fur as
# built elsewhere), lists the devices, then runs into bench-<device>/:
#   1. each section of `fur bench` alone (frame, render_quality, ...), one folder each,
#      so that a run cut short keeps what it finished;
#   2. the goal's scene (assets/scenes/goal.toml: 19,901 simulated masters, ~490K drawn
#      hairs) in the frame section at 1920x1080 (goal/): the goal is a frame under 2 ms
#      (the "GPU ms" column);
#   3. the goal's frame again with one thing changed at a time (goal-*/): samples, the
#      primitive, the hair density, culling and the image size, to show what bounds it;
#   4. the blob's frame under each lighting model, with and without shadows
#      (lighting-*/): what the Marschner model and the shadows cost;
#   5. the two strand rasterisers (hardware, compute) on the goal's scene at 1920x1080
#      (goal-raster/; the blob and the sphere are in the sections' raster/);
# and writes bench-<device>/results.md: every table. `--write-docs FILE` before any
# other argument puts the tables between FILE's `<!-- BEGIN fur gpu-bench -->` and
# `<!-- END fur gpu-bench -->` lines (docs/gpu.md).
# GPU_BENCH_PARTS (e.g. "raster lighting") runs only the parts named, in the order named:
# sections, goal, bounds, lighting, raster (the default: all, in that order).
# GPU_BENCH_SECTIONS (e.g. "raster frame") runs only those sections in the sections part.
# GPU_BENCH_TIMEOUT (seconds) stops any one `fur bench` run that takes longer, and goes on.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
choice=""
if [[ $# -gt 0 && "$1" != --* ]]; then
    choice="$1"
    shift
fi
docs=""
if [[ "${1:-}" == --write-docs ]]; then
    docs="$2"
    shift 2
fi

# FUR names a binary to use instead of building one.
if [[ -z "${FUR:-}" ]] && command -v cargo >/dev/null; then
    cargo build --release --locked
fi
fur="${FUR:-target/release/fur}"

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
mkdir -p "$out/scenes"
echo
echo "measuring $name into $out/"

# The SM clock while measuring (a GPU held at an idle clock measures nothing).
if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=timestamp,clocks.sm,utilization.gpu --format=csv,noheader,nounits \
        -lms 500 >"$out/clocks.csv" 2>/dev/null &
    sampler=$!
    trap 'kill "$sampler" 2>/dev/null || true' EXIT
fi

bench() { # folder, arguments...
    local dir=$1
    shift
    echo "== $dir"
    local limit=(timeout --signal INT --kill-after 20 "${GPU_BENCH_TIMEOUT:-0}")
    "${limit[@]}" "$fur" bench ${device_args[@]+"${device_args[@]}"} --out-dir "$out/$dir" "$@" ||
        echo "== $dir stopped or failed (exit $?); going on" >&2
}

read -r -a sections <<<"${GPU_BENCH_SECTIONS:-frame render_quality sim_accuracy sim_steps sim_scaling collision savings looks ladder animation stages raster}"
part_sections() {
    for section in "${sections[@]}"; do
        bench "$section" --only "$section" "$@"
    done
}
goal=(--only frame --width 1920 --height 1080)
part_goal() {
    bench goal "${goal[@]}" --scene assets/scenes/goal.toml "$@"
}

# The goal's frame with one thing changed: the scene files are the goal's plus a line.
variant() { # name, what it changes (scene text appended, or a sed edit)
    local file="$out/scenes/$1.toml"
    case "$2" in
        s/*) sed "$2" assets/scenes/goal.toml >"$file" ;;
        *) { cat assets/scenes/goal.toml; printf '\n%s\n' "$2"; } >"$file" ;;
    esac
}
part_bounds() {
    variant base ""
    variant samples1 $'[render]\nsamples = 1'
    variant hardware $'[render]\nraster = "hardware"'
    variant lines $'[render]\nraster = "hardware"\nprimitive = "lines"'
    variant quarter 's/^density_scale = 12.0.*/density_scale = 3.0/'
    variant bare 's/^density_scale = 12.0.*/density_scale = 0.001/'
    variant nocull $'[render]\ncull = false'
    for v in base samples1 hardware lines quarter bare nocull; do
        bench "goal-$v" "${goal[@]}" --scene "$out/scenes/$v.toml" "$@"
    done
    bench goal-half --only frame --width 960 --height 540 --scene "$out/scenes/base.toml" "$@"
    bench goal-4k --only frame --width 3840 --height 2160 --scene "$out/scenes/base.toml" "$@"
}

# The blob under each lighting model, with and without shadows.
part_lighting() {
    # Each model named (the default is the Marschner model); "shadows" is Kajiya–Kay's.
    kajiya_kay=$'[light]\nlighting_model = "kajiya-kay"'
    marschner=$'[light]\nlighting_model = "marschner"'
    shadows=$'[shadows]\nenabled = true'
    for v in kajiya-kay marschner shadows marschner-shadows; do
        case $v in
            kajiya-kay) text="$kajiya_kay" ;;
            marschner) text="$marschner" ;;
            shadows) text="$kajiya_kay"$'\n'"$shadows" ;;
            marschner-shadows) text="$marschner"$'\n'"$shadows" ;;
        esac
        printf 'model = "blob"\n%s\n' "$text" >"$out/scenes/blob-$v.toml"
        bench "lighting-$v" --only frame --scene "$out/scenes/blob-$v.toml" "$@"
    done
}

# The goal's scene drawn by each strand rasteriser.
part_raster() {
    bench goal-raster --only raster --width 1920 --height 1080 --scene assets/scenes/goal.toml "$@"
}

for p in ${GPU_BENCH_PARTS:-sections goal bounds lighting raster}; do
    case "$p" in
        sections | goal | bounds | lighting | raster) "part_$p" "$@" ;;
        *)
            echo "unknown part $p; the parts are sections, goal, bounds, lighting, raster" >&2
            exit 1
            ;;
    esac
done

bash tools/gpu-report.sh "$out" >"$out/results.md"
if [[ -n "$docs" ]]; then
    bash tools/gpu-report.sh "$out" --into "$docs"
fi

echo
echo "The tables for $name: $out/results.md (each folder's results.csv: every measurement;"
echo "*.svg: charts)."
