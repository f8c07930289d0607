#!/usr/bin/env bash
# The main job on the bundled demo data: installs what is missing, builds
# sylva, reconstructs the demo tree's density grid and fidelity report, and
# prints where the outputs are. Re-running only redoes what changed.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
sylva_install_packages
sylva_build sylva

demo="$SYLVA_ROOT/datasets/demo"
project="$SYLVA_BUILD/demo-project"
sylva="$SYLVA_BUILD/bin/sylva"
if [ ! -f "$project/sylva.json" ]; then
  sylva_log "Creating the demo project $project"
  "$sylva" init "$project" --photos "$demo/photos" --mattes "$demo/mattes" \
    --colmap "$demo/colmap" --held-out "@$demo/held_out.txt" --units m
fi
sylva_log "Running the pipeline"
"$sylva" run "$project"
sylva_log "Done. Outputs: $project/out/ (tree.glb opens in Blender or any glTF viewer; report.html in a browser)"
