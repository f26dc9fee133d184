#!/bin/bash
# Byte identity of two terrain-build binaries on the shared DEMs (issue 50: a faster build must
# write the same pyramids). Builds each input with both, one after the other (2 threads), and
# compares every shard file and the manifest but its build.seconds; prints each build's wall
# and CPU seconds. Exit status 1 if any pyramid differs.
#   tools/bench/compare_builds.sh OLD_TERRAIN_BUILD NEW_TERRAIN_BUILD [SHARED_DATA] [SCRATCH]
set -u
OLD=${1:?usage: compare_builds.sh OLD_TERRAIN_BUILD NEW_TERRAIN_BUILD [SHARED_DATA] [SCRATCH]}
NEW=${2:?usage: compare_builds.sh OLD_TERRAIN_BUILD NEW_TERRAIN_BUILD [SHARED_DATA] [SCRATCH]}
D=${3:-$(cd "$(dirname "$0")/../../.." && pwd)/shared/data}
OUT=${4:-/tmp/compare-builds}
[ -d "$D" ] || { echo "compare_builds.sh: $D: no shared data folder" >&2; exit 1; }
rm -rf "$OUT" && mkdir -p "$OUT"
different=0
compared=0
run() {  # NAME TERRAIN-BUILD-ARGUMENTS...
    local name=$1 b exe
    shift
    for b in old new; do
        exe=$OLD; [ $b = new ] && exe=$NEW
        /usr/bin/time -f "%e s, %U CPU s" -o "$OUT/$name-$b.time" \
            "$exe" "$@" -o "$OUT/$name-$b" -q --threads 2 > "$OUT/$name-$b.log" 2>&1 ||
            echo "$name: the $b build failed (see $OUT/$name-$b.log)"
    done
    compared=$((compared + 1))
    local result=identical
    if ! diff -rq -x manifest.json "$OUT/$name-old" "$OUT/$name-new" > /dev/null ||
        ! diff -q <(grep -v '"seconds"' "$OUT/$name-old/manifest.json") \
                  <(grep -v '"seconds"' "$OUT/$name-new/manifest.json") > /dev/null; then
        result=DIFFERENT
        different=$((different + 1))
    fi
    echo "$name: $result; old $(cat "$OUT/$name-old.time"); new $(cat "$OUT/$name-new.time")"
    rm -rf "$OUT/$name-old" "$OUT/$name-new"
}
R=$D/srtm3_n46w122_rainier.tif
E=$D/etopo20_global.nc
run puget1k "$D/puget_sound_1k.png" --vertical-scale 0.1 --spacing 160
run puget4k "$D/puget_sound_4k_8bit.jpg" --vertical-scale 25.7 --spacing 40
run rainier "$R"
run rainier-lossy "$R" --max-error-m 1
run rainier-blocks-2 "$R" --block-quads 2
run rainier-blocks-4 "$R" --block-quads 4
run rainier-blocks-16 "$R" --block-quads 16
run rainier-blocks-64 "$R" --block-quads 64
run rainier-patch-65 "$R" --patch-size 65
run rainier-by-shards "$R" --by-shards
run n57 "$D/srtm/N57E011.hgt"
run kilauea "$D/kilauea_utm5n_30m.nc"
run etopo "$E"
run luxembourg "$D/luxembourg_elev_30s.tif"
run globe-etopo-rainier "$E" "$R" --globe
run globe-etopo-rainier-lossy "$E" "$R" --globe --max-error-m 1
run globe-rainier "$R" --globe
run globe-rainier-by-shards "$R" --globe --by-shards
run globe-kilauea "$D/kilauea_utm5n_30m.nc" --globe
run globe-n57 "$D/srtm/N57E011.hgt" --globe
run globe-luxembourg "$D/luxembourg_elev_30s.tif" --globe
run globe-etopo-by-shards "$E" --globe --by-shards
echo "$different of $compared pyramids differ"
[ $different -eq 0 ]
