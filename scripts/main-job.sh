#!/usr/bin/env bash
# README command 1: install every Debian package, build, and run the main job on the
# built-in default (the procedural terrain; no download). For now the main job is the
# preview: generate the default 1025² procedural DEM and render one tessellated view of
# it headless to out/terrain.png, with its JSON summary in out/terrain.json.
# Extra options go to terrain-render (see build/tools/terrain-render/terrain-render --help).
set -euo pipefail
repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$repo_root/scripts/setup.sh"

out="$repo_root/out"
mkdir -p "$out"
"$repo_root/build/tools/terrain-render/terrain-render" -o "$out/terrain.png" --json "$@" \
  > "$out/terrain.json.tmp"
mv "$out/terrain.json.tmp" "$out/terrain.json"
cat "$out/terrain.json"
echo "main job: wrote $out/terrain.png and $out/terrain.json"
