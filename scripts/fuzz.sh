#!/usr/bin/env bash
# Builds the fuzz targets of tools/fuzz with clang (libFuzzer, ASan + UBSan, every library
# instrumented) and runs each on its corpus for a fixed time; writes, per target,
# executions, coverage (edges "cov" and features "ft"), corpus size and findings to JSON.
# Exits 1 on any finding (crash, leak, timeout, out-of-memory): its input is kept under
# <build-dir>/findings/<target>/; fix it and add it to tests/fuzz/<target>/.
#
#   scripts/fuzz.sh --smoke                  CI: 15 s a target
#   scripts/fuzz.sh --seconds 200 --json f   the benchmark (9 targets: 30 min of fuzzing)
# Options: --seconds N (a target; default 60), --timeout S (an input; default 10, 60 with
#          --smoke), --targets "manifest shard ..." (default all),
#          --parallel K (targets at once; default 1), --json FILE
#          (default <build-dir>/fuzz-report.json), --build-dir DIR (default build-fuzz).
# The corpus grows in <build-dir>/corpus/<target>/ from run to run; each run starts from the
# target's seeds (written by the target itself) and the regression inputs in tests/fuzz/.
set -euo pipefail
repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="$repo_root/build-fuzz"
seconds=60
timeout=10
parallel=1
json=""
seed=()
targets="manifest shard imagery-tiles camera-path dem-tiff dem-png dem-exr dem-hgt dem-netcdf dem-asc"
while [ $# -gt 0 ]; do
  case "$1" in
    # The same mutations each CI run, and a longer limit an input: CI machines are shared
    # and slow (a hello-world compile took 13 s on one), and under ASan an ordinary input
    # can take seconds there; a smoke run must not call that a hang. A fuzzing run keeps
    # 10 s: there it is one. (The input that once took 40 s, dem-exr/data-window-8M-columns.exr,
    # is now refused by the OpenEXR header walk before anything is allocated.)
    --smoke) seconds=15; timeout=60; seed=(-seed=1) ;;
    --timeout) timeout=$2; shift ;;
    --seconds) seconds=$2; shift ;;
    --targets) targets=$2; shift ;;
    --parallel) parallel=$2; shift ;;
    --json) json=$2; shift ;;
    --build-dir) build_dir=$2; shift ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
case "$build_dir" in /*) ;; *) build_dir="$PWD/$build_dir" ;; esac
json=${json:-$build_dir/fuzz-report.json}

"$repo_root/scripts/setup.sh" --deps-only
CC=clang CXX=clang++ cmake -S "$repo_root" -B "$build_dir" -G Ninja \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTERRAIN_FUZZ=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
  -DTERRAIN_SANITIZER="address;undefined" -DTERRAIN_BUILD_TESTS=OFF \
  -DTERRAIN_UNITY_BUILD=OFF -DTERRAIN_USE_MOLD=OFF \
  -DTERRAIN_WARNINGS_AS_ERRORS=ON > /dev/null
cmake --build "$build_dir" --target terrain-fuzzers --parallel "$(nproc)"

export ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
logs="$build_dir/logs"
mkdir -p "$logs"

fuzz_one() {
  local target=$1
  local bin="$build_dir/tools/fuzz/fuzz-$target"
  local seeds="$build_dir/seeds/$target" corpus="$build_dir/corpus/$target"
  local findings="$build_dir/findings/$target"
  rm -rf "$seeds" "$findings"
  mkdir -p "$seeds" "$corpus" "$findings"
  # The target writes its seeds (and runs them once); JSON targets get their keys as a
  # dictionary.
  TERRAIN_FUZZ_SEEDS="$seeds" "$bin" -runs=0 "$seeds" > "$logs/$target.seeds.log" 2>&1 || true
  cp -n "$seeds"/* "$corpus"/
  local dict=()
  if [ "$target" = manifest ] || [ "$target" = camera-path ]; then
    grep -ohE '"[A-Za-z_][A-Za-z0-9_]*"' "$seeds"/* | sort -u | sed 's/"/\\"/g; s/.*/"&"/' \
      > "$build_dir/$target.dict"
    dict=(-dict="$build_dir/$target.dict")
  elif [ -f "$repo_root/tools/fuzz/${target#dem-}.dict" ]; then
    dict=(-dict="$repo_root/tools/fuzz/${target#dem-}.dict")
  fi
  local regressions=()
  [ -d "$repo_root/tests/fuzz/$target" ] && regressions=("$repo_root/tests/fuzz/$target")
  local rc=0 started
  started=$(date +%s%N)
  "$bin" "$corpus" "${regressions[@]}" "${dict[@]}" "${seed[@]}" -max_total_time="$seconds" -timeout="$timeout" \
    -rss_limit_mb=4096 -malloc_limit_mb=2560 -print_final_stats=1 \
    -artifact_prefix="$findings/" > "$logs/$target.log" 2>&1 || rc=$?
  echo "$rc" > "$logs/$target.rc"
  echo "$(( $(date +%s%N) - started ))" > "$logs/$target.ns"  # wall time of the run
  echo "fuzz.sh: $target: exit $rc, $(grep -E '^#[0-9]+' "$logs/$target.log" | tail -1 | cut -c1-100)"
}

running=0
for target in $targets; do
  [ -x "$build_dir/tools/fuzz/fuzz-$target" ] || { echo "fuzz.sh: no target '$target'" >&2; exit 2; }
  fuzz_one "$target" &
  running=$((running + 1))
  if [ "$running" -ge "$parallel" ]; then wait -n; running=$((running - 1)); fi
done
wait

python3 "$repo_root/tools/fuzz/fuzz_report.py" --logs "$logs" --findings "$build_dir/findings" \
  --seconds "$seconds" --parallel "$parallel" --targets $targets -o "$json"
