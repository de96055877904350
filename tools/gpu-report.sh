#!/usr/bin/env bash
# Assembles the tables of one run of tools/gpu-bench.sh (its folder bench-<device>/) into
# one Markdown text, on standard output:
#
#   bash tools/gpu-report.sh bench-nvidia-h100-80gb-hbm3
#
# or, with `--into FILE`, between FILE's `<!-- BEGIN fur gpu-bench -->` and
# `<!-- END fur gpu-bench -->` lines (docs/gpu.md). Nothing in it is typed by hand: every
# figure is copied from the run's results.md files.
set -euo pipefail

dir="${1:?usage: gpu-report.sh BENCH_DIR [--into FILE]}"
into=""
if [[ "${2:-}" == --into ]]; then
    into="${3:?--into needs a file}"
fi

sections=(frame render_quality sim_accuracy sim_steps sim_scaling collision savings looks
    ladder animation stages raster)

# A section's tables without the file's title and device lines.
tables() { tail -n +4 "$1"; }

report() {
    local first
    first="$(find "$dir" -mindepth 2 -maxdepth 2 -name results.md | sort | head -n 1)"
    [[ -n "$first" ]] || {
        echo "$dir holds no results.md" >&2
        return 1
    }
    sed -n 3p "$first"
    echo
    if [[ -f "$dir/clocks.csv" ]]; then
        # timestamp, SM MHz, utilisation %: the clock over the samples with work.
        awk -F ', *' '$3 + 0 > 0 { print $2 + 0 }' "$dir/clocks.csv" | sort -n | awk '
            { c[NR] = $1 }
            END { if (NR) { for (i = 1; i <= NR; i++) top += c[i] == c[NR]
                printf "SM clock while busy (nvidia-smi every 0.5 s): median %d MHz; %d of %d samples at the highest, %d MHz.\n\n", c[int((NR + 1) / 2)], top, NR, c[NR] } }'
    fi
    echo "Each section ran alone (\`fur bench --only SECTION\`), one after another in one run."
    for s in "${sections[@]}"; do
        [[ -f "$dir/$s/results.md" ]] && tables "$dir/$s/results.md"
    done
    if [[ -f "$dir/goal/results.md" ]]; then
        echo
        echo "## The goal's frame"
        echo
        echo "\`assets/scenes/goal.toml\` at 1920×1080: the goal is a frame under 2 ms (GPU ms)."
        tables "$dir/goal/results.md" | sed 's/^## /### /'
    fi
    if [[ -f "$dir/goal-raster/results.md" ]]; then
        echo
        echo "## The goal's frame, each strand rasteriser"
        echo
        echo "\`assets/scenes/goal.toml\` at 1920×1080 (\`fur bench --only raster\`)."
        tables "$dir/goal-raster/results.md" | sed 's/^## /### /'
    fi
    echo
    [[ -f "$dir/goal-base/results.md" ]] || { lighting; return 0; }
    echo "## What bounds the goal's frame"
    echo
    echo "The goal's default frame again, each row changing one thing (the scene file's"
    echo "line, or the image size); GPU ms is the whole frame's, fur pass ms the fur pass"
    echo "timed alone, both medians after warm-up; the ratio is to the first row."
    echo
    echo "| change | hairs drawn | segments | GPU ms | fur pass ms | × the goal's GPU ms |"
    echo "| --- | --- | --- | --- | --- | --- |"
    local base=""
    local rows=(
        "base|none: the default drawing (strands in compute) at 1920×1080"
        "samples1|\`samples = 1\` (no MSAA)"
        "hardware|\`raster = \"hardware\"\` (4× MSAA ribbons)"
        "lines|\`raster = \"hardware\"\`, \`primitive = \"lines\"\`"
        "quarter|\`density_scale = 3\` (a quarter of the density)"
        "bare|\`density_scale = 0.001\` (almost no hairs: the fixed cost)"
        "nocull|\`cull = false\`"
        "half|960×540 (a quarter of the pixels)"
        "4k|3840×2160 (four times the pixels)"
    )
    for row in "${rows[@]}"; do
        local what="${row#*|}" file="$dir/goal-${row%%|*}/results.md"
        [[ -f "$file" ]] || continue
        # The default drawing's row, then the passes' row (its second cell a number).
        local frame passes
        frame="$(awk -F ' *[|] *' '$3 == "default" { print $4, $5, $7; exit }' "$file")"
        passes="$(awk -F ' *[|] *' '$3 ~ /^[0-9.]+$/ { print $5; exit }' "$file")"
        read -r hairs segments gpu <<<"$frame"
        [[ -z "$base" ]] && base="$gpu"
        local ratio
        ratio="$(awk -v a="$gpu" -v b="$base" 'BEGIN { printf "%.2f×", a / b }')"
        echo "| $what | $hairs | $segments | $gpu | $passes | $ratio |"
    done
    lighting
}

# The table of the lighting part, when the run has it.
lighting() {
    [[ -f "$dir/lighting-kajiya-kay/results.md" ]] || return 0
    echo
    echo "## What the lighting costs"
    echo
    echo "The default blob at 1280×720 under each lighting model, without and with"
    echo "shadows (the scene file's lines); medians after warm-up as above; the ratio is"
    echo "to Kajiya–Kay without shadows."
    echo
    echo "| lighting | GPU ms | fur pass ms | × Kajiya–Kay |"
    echo "| --- | --- | --- | --- |"
    local base=""
    for row in "kajiya-kay|Kajiya–Kay" "marschner|Marschner" "shadows|Kajiya–Kay, shadows on" \
        "marschner-shadows|Marschner, shadows on"; do
        local file="$dir/lighting-${row%%|*}/results.md"
        [[ -f "$file" ]] || continue
        local gpu passes ratio
        gpu="$(awk -F ' *[|] *' '$3 == "default" { print $7; exit }' "$file")"
        passes="$(awk -F ' *[|] *' '$3 ~ /^[0-9.]+$/ { print $5; exit }' "$file")"
        [[ -z "$base" ]] && base="$gpu"
        ratio="$(awk -v a="$gpu" -v b="$base" 'BEGIN { printf "%.2f×", a / b }')"
        echo "| ${row#*|} | $gpu | $passes | $ratio |"
    done
}

if [[ -z "$into" ]]; then
    report
    exit 0
fi
grep -q '^<!-- BEGIN fur gpu-bench -->$' "$into" && grep -q '^<!-- END fur gpu-bench -->$' "$into" || {
    echo "$into has no <!-- BEGIN fur gpu-bench --> ... <!-- END fur gpu-bench --> lines" >&2
    exit 1
}
text="$(mktemp)"
report >"$text"
tmp="$(mktemp "$(dirname "$into")/.gpu-report.XXXXXX")"
awk -v text="$text" '
    /^<!-- BEGIN fur gpu-bench -->$/ { print; while ((getline line < text) > 0) print line; skip = 1; next }
    /^<!-- END fur gpu-bench -->$/ { skip = 0 }
    !skip { print }
' "$into" >"$tmp"
chmod --reference="$into" "$tmp"
mv "$tmp" "$into"
rm -f "$text"
echo "wrote the tables of $dir into $into"
