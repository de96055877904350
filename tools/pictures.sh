#!/usr/bin/env bash
# Regenerates the pictures in assets/gallery/ that the README, docs/design.md and
# docs/scene-files.md show, each by the command its caption names (the path-traced
# truth pictures come from `fur bench --only truth`; docs/pipeline/ from
# tools/gallery.sh). Everything is seeded: two runs on one machine write the same bytes.
# Run from anywhere: tools/pictures.sh [fur binary] (empty: builds the release one).
set -euo pipefail
cd "$(dirname "$0")/.."
fur=${1:-}
if [[ -z $fur ]]; then
    cargo build --release --locked --quiet
    fur=./target/release/fur
fi
out=assets/gallery
small=(--width 320 --height 180)
tmp=$(mktemp -d)
trap 'rm -r "$tmp"' EXIT
# The shipped scenes, each its 40th frame (docs/scene-files.md).
for scene in default original combed_wind velvet curly; do
    echo "$scene: fur render assets/scenes/$scene.toml --frames 40"
    "$fur" render "assets/scenes/$scene.toml" --frames 40 "${small[@]}" --out-dir "$tmp/$scene" >/dev/null
    cp "$tmp/$scene/frame_0039.png" "$out/$scene.png"
done
# Each look alone over none, then all four, lit by Kajiya–Kay, whose look the
# secondary highlight is (docs/design.md, "Looks").
look() {
    local name=$1
    shift
    echo "looks_$name: fur render --lighting-model kajiya-kay $*"
    "$fur" render "${small[@]}" --lighting-model kajiya-kay "$@" --out "$out/looks_$name.png" >/dev/null
}
look plain --secondary-highlight off --thin-hair-aa off --shadows off
look texture --secondary-highlight off --thin-hair-aa off --shadows off --texture tabby
look secondary --secondary-highlight on --thin-hair-aa off --shadows off
look shadows --secondary-highlight off --thin-hair-aa off --shadows on
look thin_aa --secondary-highlight off --thin-hair-aa on --shadows off
look all --texture tabby --shadows on
# The walking critter (README): frames 28, 32, 36; frame 32 without collision too.
echo "critter_walk: fur render assets/scenes/critter.toml --frames 40"
"$fur" render assets/scenes/critter.toml --frames 40 "${small[@]}" --out-dir "$tmp/walk" >/dev/null
for frame in 28 32 36; do
    cp "$tmp/walk/frame_00$frame.png" "$out/critter_walk_$frame.png"
done
"$fur" render assets/scenes/critter.toml --frames 33 --collision off "${small[@]}" --out-dir "$tmp/loose" >/dev/null
cp "$tmp/loose/frame_0032.png" "$out/critter_walk_no_collision.png"
# A model brought as a file, furred with the defaults (README).
echo "critter_obj: fur render --model critter.obj --distance 2.2 --yaw 40 --pitch 10"
"$fur" export-model "$tmp/critter.obj" --model critter >/dev/null
"$fur" render --model "$tmp/critter.obj" --distance 2.2 --yaw 40 --pitch 10 "${small[@]}" \
    --out "$out/critter_obj.png" >/dev/null
echo "wrote the pictures into $out"
