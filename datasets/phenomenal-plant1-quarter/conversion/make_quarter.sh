#!/usr/bin/env bash
# Makes phenomenal-plant1-quarter from sylva's shared phenomenal-plant1 folder:
# every photo and silhouette at a quarter of its size (box filter), the COLMAP
# model scaled to match. Needs oiiotool (Debian openimageio-tools).
#   bash conversion/make_quarter.sh SHARED/phenomenal-plant1 OUT_DIR
set -euo pipefail
src=$1
out=$2
mkdir -p "$out/raw/side" "$out/raw/top" "$out/bin/side" "$out/bin/top" "$out/colmap"
# Side photos are 2056 x 2454 and the top photo 2454 x 2056: two rows (side)
# or columns (top) are cut so that both sides divide by 4 (the principal
# point does not move), then each 4 x 4 block is averaged.
for f in "$src"/raw/side/*.jpg; do
  oiiotool "$f" --cut 2056x2452+0+0 --resize:filter=box 514x613 --quality 92 -o "$out/raw/side/$(basename "$f")"
done
oiiotool "$src/raw/top/0.jpg" --cut 2452x2056+0+0 --resize:filter=box 613x514 --quality 92 -o "$out/raw/top/0.jpg"
for f in "$src"/bin/side/*.png; do
  oiiotool "$f" --ch 0 --cut 2056x2452+0+0 --resize:filter=box 514x613 -d uint8 -o "$out/bin/side/$(basename "$f")"
done
oiiotool "$src/bin/top/0.png" --ch 0 --cut 2452x2056+0+0 --resize:filter=box 613x514 -d uint8 -o "$out/bin/top/0.png"
# Cameras: focal lengths and principal points divided by 4 (COLMAP's pixel
# convention: continuous image coordinates scale with the image).
awk '/^#/ {print; next} NF >= 8 {printf "%s %s %d %d %.10f %.10f %.4f %.4f\n", $1, $2, ($1 == 1 ? 514 : 613), ($1 == 1 ? 613 : 514), $5 / 4, $6 / 4, $7 / 4, $8 / 4}' \
  "$src/colmap/cameras.txt" > "$out/colmap/cameras.txt"
cp "$src/colmap/images.txt" "$src/colmap/points3D.txt" "$out/colmap/"
cp "$src/LICENSE.txt" "$out/"
(cd "$out" && sha256sum raw/side/*.jpg raw/top/*.jpg bin/side/*.png bin/top/*.png colmap/*.txt LICENSE.txt > SHA256SUMS)
