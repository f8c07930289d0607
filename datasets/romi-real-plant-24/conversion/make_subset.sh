#!/bin/bash
# Makes datasets/romi-real-plant-24 from the full ROMI real_plant v1 set
# (sylva's shared dataset folder romi-real-plant): every third photo of the
# 72-photo circle (24 photos, 15 degrees apart), byte-identical, with the
# matching lines of the COLMAP text model and the scan metadata.
# Usage: make_subset.sh SRC_DIR DST_DIR   (needs coreutils and awk only)
set -euo pipefail
src=$1
dst=$2
mkdir -p "$dst/images" "$dst/colmap"
names=$(ls "$src/images" | sort | awk 'NR % 3 == 1')
for n in $names; do cp "$src/images/$n" "$dst/images/$n"; done
cp "$src/colmap/cameras.txt" "$src/colmap/points3D.txt" "$dst/colmap/"
awk -v keep="$(echo $names)" '
  BEGIN { n = split(keep, k, " "); for (i = 1; i <= n; i++) want[k[i]] = 1 }
  /^#/ { if ($0 ~ /Number of images/) print "# Number of images: " n ", mean observations per image: 0"; else print; next }
  { if (want[$10]) { print; print "" } }
' "$src/colmap/images.txt" > "$dst/colmap/images.txt"
cp "$src/metadata/metadata.json" "$dst/metadata.json"
cp "$src/LICENSE" "$dst/LICENSE"
