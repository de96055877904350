#!/usr/bin/env bash
# Regenerates the pictures of docs/pipeline.md: one `fur render --show STAGE` per stage
# view of the default scene, and the "try this" variations, into docs/pipeline/ (or
# OUT_DIR). Everything is seeded: two runs on one machine write the same bytes.
# Run from anywhere: tools/gallery.sh [fur binary] [OUT_DIR] [fur render options...]
# e.g. tools/gallery.sh "" mine --model creature.glb   (every stage of your own model;
# an empty binary builds and uses the release one).
set -euo pipefail
cd "$(dirname "$0")/.."
fur=${1:-}
out=${2:-docs/pipeline}
extra=("${@:3}")
if [[ -z $fur ]]; then
    cargo build --release --locked --quiet
    fur=./target/release/fur
fi
mkdir -p "$out"
size=(--width 480 --height 270 "${extra[@]}")
shot() {
    local name=$1
    shift
    echo "$name: fur render $*"
    "$fur" render "${size[@]}" "$@" --out "$out/$name.png" >/dev/null
}
# The 30th frame of the scripted shake (a simulated sequence keeps its last frame).
simulated() {
    local name=$1
    shift
    echo "$name: fur render --frames 30 --motion shake $*"
    local tmp
    tmp=$(mktemp -d)
    "$fur" render "${size[@]}" --frames 30 --motion shake "$@" --out-dir "$tmp" >/dev/null
    cp "$tmp/frame_0029.png" "$out/$name.png"
    rm -r "$tmp"
}
for stage in masters interpolated density lod shadow lit; do
    shot "$stage" --show "$stage"
done
# Ownership at four times the density: triangles with points inside as well as on
# their edges.
shot ownership --show ownership --density-scale 4
shot tiles --show tiles
# Try this: one parameter changed, one stage shown.
shot masters-comb --show masters --comb 0
shot masters-direction --show masters --flow direction
shot interpolated-dense --show interpolated --density-scale 3
shot density-near --show density --lod-distance 0.5
shot lod-near --show lod --lod-distance 0.5
# The simulation: soft and stiff hair, how far it moved, and one step's corrections.
for stiffness in 0.05 0.9; do
    simulated "simulated-$stiffness" --local-stiffness "$stiffness" --show masters
done
simulated simulation --show simulation
simulated simulation-arrows --show simulation --arrows local --arrow-scale 100
echo "wrote $(ls "$out" | wc -l) pictures into $out"
