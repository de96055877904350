#!/usr/bin/env bash
# Regenerates the pictures of docs/pipeline.md: one `fur render --show STAGE` per stage
# view of the default scene, and the "try this" variations, into docs/pipeline/.
# Run from anywhere: tools/gallery.sh [fur binary]
set -euo pipefail
cd "$(dirname "$0")/.."
fur=${1:-}
if [[ -z $fur ]]; then
    cargo build --release --locked --quiet
    fur=./target/release/fur
fi
out=docs/pipeline
mkdir -p "$out"
size=(--width 480 --height 270)
shot() {
    local name=$1
    shift
    echo "$name: fur render $*"
    "$fur" render "${size[@]}" "$@" --out "$out/$name.png" >/dev/null
}
for stage in masters interpolated lod shadow lit; do
    shot "$stage" --show "$stage"
done
# Ownership at four times the density: triangles with points inside as well as on
# their edges.
shot ownership --show ownership --density-scale 4
# Try this: one parameter changed, one stage shown.
shot masters-comb --show masters --comb 0
shot interpolated-dense --show interpolated --density-scale 3
shot lod-near --show lod --lod-distance 0.5
# The simulation: the 30th frame of the scripted shake, with soft and stiff hair.
for stiffness in 0.05 0.9; do
    tmp=$(mktemp -d)
    echo "simulated-$stiffness: fur render --frames 30 --motion shake --local-stiffness $stiffness --show masters"
    "$fur" render "${size[@]}" --frames 30 --motion shake --local-stiffness "$stiffness" \
        --show masters --out-dir "$tmp" >/dev/null
    cp "$tmp/frame_0029.png" "$out/simulated-$stiffness.png"
    rm -r "$tmp"
done
echo "wrote $(ls "$out" | wc -l) pictures into $out"
