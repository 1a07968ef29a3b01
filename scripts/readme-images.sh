#!/usr/bin/env bash
# Regenerates the images the README shows (needs a build and oiiotool from openimageio-tools for
# the mosaics): every mode on the ch2 head and on the large ch2better head.
set -euo pipefail
cd "$(dirname "$0")/.."
penumbra=build/release/server/app/penumbra
out=docs/images
mkdir -p "$out" out/modes
mapfile -t modes < <("$penumbra" render --list-modes)
for volume in ch2 ch2better; do
    tiles=()
    for mode in "${modes[@]}"; do
        "$penumbra" render --volume "/usr/share/mricron/templates/$volume.nii.gz" --mode "$mode" \
            --phong --size 256x256 --camera 35,5,2.4 --light 75,35 --intensity 1.2 \
            --slices 256 --light-res 256 --out "out/modes/${volume}_$mode.png" >/dev/null
        tiles+=("out/modes/${volume}_$mode.png")
    done
    oiiotool "${tiles[@]}" --mosaic "${#modes[@]}x1" -o "$out/${volume}_modes.png"
done
"$penumbra" render --mode sbrc --phong --size 512x512 --camera 35,5,2.4 --light 75,35 \
    --intensity 1.2 --slices 256 --light-res 256 --out "$out/ch2_sbrc.png" \
    --light-inset "$out/ch2_sbrc_inset.png" >/dev/null
# The light lookups side by side, with the light where the paper's shows its slice rings: the
# paper's (one point per slab, interpolating between layers), ours (the default), the reference.
lookups=()
for variant in "interpolate 1" "local 0"; do
    set -- $variant
    "$penumbra" render --mode sbrc --phong --size 256x256 --light-lookup "$1" --slab-samples "$2" \
        --out "out/modes/ch2_lookup_$1.png" >/dev/null
    lookups+=("out/modes/ch2_lookup_$1.png")
done
"$penumbra" render --mode reference --phong --size 256x256 --out out/modes/ch2_lookup_reference.png \
    >/dev/null
oiiotool "${lookups[@]}" out/modes/ch2_lookup_reference.png --mosaic 3x1 -o "$out/ch2_light_lookup.png"
# The head CT cut open at the midline, seen from the left with the light from the left: the cut
# tissue casting no shadow (the default), casting it (--cut-shadows), and the soft tissue.
ct=build/release/data/cranium_ct.nrrd
cut=(--volume "$ct" --mode sbrc --phong --view left --size 256x256 --crop 122,250,-10,250,-10,170
     --light -60,30)
"$penumbra" render "${cut[@]}" --out "$out/cranium_ct_cut_dissection.png" >/dev/null
"$penumbra" render "${cut[@]}" --cut-shadows --out "$out/cranium_ct_cut_context.png" >/dev/null
"$penumbra" render "${cut[@]}" --tf ct_soft_tissue --out "$out/cranium_ct_cut_soft_tissue.png" \
    >/dev/null
