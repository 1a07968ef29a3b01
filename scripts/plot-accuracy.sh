#!/usr/bin/env bash
# The committed accuracy table and plot (docs/accuracy/llvmpipe.*), from `penumbra bench accuracy`.
#   scripts/plot-accuracy.sh            redraw presets, CSV and plot from the committed JSON
#   scripts/plot-accuracy.sh --measure  measure again: the reduced sweep that fits llvmpipe
#                                       (~6 minutes on 2 cores), then write everything
# Needs a release build (scripts/build.sh) and gnuplot (scripts/install-deps.sh installs it).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
penumbra="${PENUMBRA:-$root/build/release/server/app/penumbra}"
out="$root/docs/accuracy"
templates=/usr/share/mricron/templates
budgets=100,150,200,300,400,500,1000

mkdir -p "$out"
if [ "${1:-}" = "--measure" ]; then
    # Two heads (7 and 35 million voxels), a light near the view and one from the side.
    "$penumbra" bench accuracy \
        --volumes "$templates/ch2.nii.gz,$templates/ch2better.nii.gz" --lights "10,45;100,20" \
        --size 256x256 --slices-list 32,64,128,256 --light-res-list 64,128,256 \
        --sample-distances 1/256 --repeat 3 --budget-ms "$budgets" \
        --csv "$out/llvmpipe.csv" --json "$out/llvmpipe.json" --plot "$out/llvmpipe.png"
else
    "$penumbra" bench accuracy --from "$out/llvmpipe.json" --budget-ms "$budgets" \
        --csv "$out/llvmpipe.csv" --json "$out/llvmpipe.json" --plot "$out/llvmpipe.png"
fi
