#!/usr/bin/env bash
# README command 1: install every Debian package, build, and run the main job on the
# built-in defaults (procedural terrain and planet; no download):
#  1. build the default 1025² procedural DEM into a pyramid (out/procedural.pyramid) with
#     every error bound, and verify the pyramid against the DEM it came from;
#  2. fly the built-in procedural planet (the virtual globe pyramid "planet:", its patches
#     generated on the I/O thread as the view asks for them) headless from orbit down to 1 m
#     above its highest mountain on the WGS84 ellipsoid (streaming, the globe LOD, one
#     tessellated draw per frame): PNG frames and telemetry.csv in out/render/, the JSON
#     summary in out/render.json.
# Extra options go to terrain-render (see build/tools/terrain-render/terrain-render --help).
set -euo pipefail
repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$repo_root/scripts/setup.sh"

tools="$repo_root/build/tools"
out="$repo_root/out"
mkdir -p "$out"
source="procedural:size=1025,seed=1"

"$tools/terrain-build/terrain-build" "$source" -o "$out/procedural.pyramid" --overwrite --json \
  > "$out/build.json.tmp"
mv "$out/build.json.tmp" "$out/build.json"
"$tools/terrain-inspect/terrain-inspect" "$out/procedural.pyramid" --verify --source "$source"

"$tools/terrain-render/terrain-render" planet: -o "$out/render" --fps 15 --every 15 --json "$@" \
  > "$out/render.json.tmp"
mv "$out/render.json.tmp" "$out/render.json"
echo "main job: wrote $out/procedural.pyramid ($out/build.json); flew planet: from orbit to 1 m" \
  "above its highest mountain: frames and telemetry.csv in $out/render/ ($out/render.json)"
