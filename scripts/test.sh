#!/usr/bin/env bash
# README command 2: install every Debian package, build (warnings are errors) and run
# the whole test suite. Extra options go to setup.sh (e.g. --sanitizer "address;undefined"
# --build-dir build-asan), except --tests REGEX, which runs only the tests whose names
# match (ctest -R), and --labels REGEX, only the tests whose labels match (ctest -L).
set -euo pipefail
repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="$repo_root/build"
tests_regex=""
labels_regex=""
setup_args=()
while [ $# -gt 0 ]; do
  case $1 in
    --tests) tests_regex=$2; shift ;;
    --labels) labels_regex=$2; shift ;;
    --build-dir) build_dir=$2; setup_args+=("$1" "$2"); shift ;;
    *) setup_args+=("$1") ;;
  esac
  shift
done

"$repo_root/scripts/setup.sh" "${setup_args[@]}"

# GCC 12's sanitizer runtime (Debian 12) misreads some dynamic TLS blocks (Mesa's driver
# has them) as pre-2.25 glibc headers in its __tls_get_addr interceptor, and LeakSanitizer's
# tracer then dies at exit with "Tracer caught signal 11" after a test has passed, in
# about one process in a few hundred. Not intercepting it avoids that (GCC 14 fixed it).
export ASAN_OPTIONS="intercept_tls_get_addr=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export TSAN_OPTIONS="halt_on_error=1:suppressions=$repo_root/tests/tsan.supp${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
cd "$build_dir"
ctest --output-on-failure --no-tests=error --parallel 2 --timeout 1800 ${tests_regex:+-R "$tests_regex"} \
  ${labels_regex:+-L "$labels_regex"}
