#!/usr/bin/env bash
# The demo data folder `penumbra serve` offers by default: InVesalius' head CT (Debian's
# invesalius-examples) converted into a NRRD by scripts/cranium-ct.py, beside links to the MRI
# heads of Debian's mricron-data. Kept in $XDG_CACHE_HOME/penumbra/volumes (else
# ~/.cache/penumbra/volumes); nothing of it is committed. Run again after either package changes:
# the conversion is skipped while the NRRD is newer than the .inv3.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
folder="${XDG_CACHE_HOME:-$HOME/.cache}/penumbra/volumes"
mkdir -p "$folder"
/usr/bin/python3 "$here/cranium-ct.py" "$folder/cranium_ct.nrrd"
for head in /usr/share/mricron/templates/*.nii.gz; do
    ln -sfn "$head" "$folder/$(basename "$head")"
done
echo "demo-data: $folder"
