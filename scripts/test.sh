#!/usr/bin/env bash
# README command 2: install every Debian package, build (warnings are errors) and run
# the whole test suite. Extra options go to setup.sh (e.g. --sanitizer "address;undefined"
# --build-dir build-asan).
set -euo pipefail
repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="$repo_root/build"
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  [ "${args[$i]}" = "--build-dir" ] && build_dir=${args[$((i + 1))]}
done

"$repo_root/scripts/setup.sh" "$@"

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export TSAN_OPTIONS="halt_on_error=1${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
cd "$build_dir"
ctest --output-on-failure --parallel 2 --timeout 600
