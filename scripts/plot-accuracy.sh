#!/usr/bin/env bash
# The committed accuracy tables and plots (docs/accuracy/llvmpipe*.*), from `penumbra bench
# accuracy`: llvmpipe.* is ch2's opaque skin (mri_skin) and the head CT's bone (ct_bone) at two
# sample distances, against the converged truth; llvmpipe_mri_brain.* and
# llvmpipe_ct_soft_tissue.* are the translucent cases, each with empty-space skipping on and off,
# jitter off and on, and jittered stills refined by 4 and 8 steps.
#   scripts/plot-accuracy.sh            redraw presets, CSV and plots from the committed JSON
#   scripts/plot-accuracy.sh --measure  measure again: the reduced sweeps that fit llvmpipe
#                                       (~3 minutes for the first, ~2 for each translucent case,
#                                       on 2 shared cores, and 30-50 s for each truth not kept yet
#                                       in ~/.cache/penumbra/truth), then write everything
# Needs a release build (scripts/build.sh; the CT case needs its `cranium_ct` target) and gnuplot
# (scripts/install-deps.sh installs it).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
penumbra="${PENUMBRA:-$root/build/release/server/app/penumbra}"
ct="${PENUMBRA_CT:-$root/build/release/data/cranium_ct.nrrd}"
out="$root/docs/accuracy"
templates=/usr/share/mricron/templates
budgets=100,150,200,300,400,500,1000
translucent_budgets=50,100,200,400,800

mkdir -p "$out"
# Small frames, the finest reference at 1/512 so that refinement has something to approach.
translucent=(--size 128x128 --modes phong,half_angle,sbrc,sbrc_cone --slices-list 32,64,128,256
    --light-res-list 128 --sample-distances 1/256,1/512 --skipping on,off --jitter off,on
    --refinement 4,8 --repeat 2 --budget-ms "$translucent_budgets")
if [ "${1:-}" = "--measure" ]; then
    # An MRI head's skin and a CT's bone (each volume's default transfer function), the light
    # near the view, at the default sample distance and half of it: what the step costs beside
    # what the light buffer costs.
    "$penumbra" bench accuracy \
        --volumes "$templates/ch2.nii.gz,$ct" --lights 10,45 \
        --size 256x256 --slices-list 32,64,128,256 --light-res-list 64,128,256 \
        --sample-distances 1/256,1/512 --repeat 3 --budget-ms "$budgets" \
        --csv "$out/llvmpipe.csv" --json "$out/llvmpipe.json" --plot "$out/llvmpipe.png"
    "$penumbra" bench accuracy --case mri_brain "${translucent[@]}" \
        --csv "$out/llvmpipe_mri_brain.csv" --json "$out/llvmpipe_mri_brain.json" \
        --plot "$out/llvmpipe_mri_brain.png"
    "$penumbra" bench accuracy --case ct_soft_tissue --volumes "$ct" "${translucent[@]}" \
        --csv "$out/llvmpipe_ct_soft_tissue.csv" --json "$out/llvmpipe_ct_soft_tissue.json" \
        --plot "$out/llvmpipe_ct_soft_tissue.png"
else
    "$penumbra" bench accuracy --from "$out/llvmpipe.json" --budget-ms "$budgets" \
        --csv "$out/llvmpipe.csv" --json "$out/llvmpipe.json" --plot "$out/llvmpipe.png"
    for name in mri_brain ct_soft_tissue; do
        "$penumbra" bench accuracy --from "$out/llvmpipe_$name.json" \
            --budget-ms "$translucent_budgets" --csv "$out/llvmpipe_$name.csv" \
            --json "$out/llvmpipe_$name.json" --plot "$out/llvmpipe_$name.png"
    done
fi
