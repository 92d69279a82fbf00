#!/usr/bin/env bash
# Sets up (packages, data, Release build) and runs the whole test suite with CTest.
# --sanitize: the same suite built with ASan and UBSan instead (CMakePresets.json's `sanitize`,
# in build-sanitize/), where any error a sanitizer reports, a leak included, fails its test.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  shift
  scripts/setup.sh --no-build
  mkdir -p build-sanitize
  cmake --preset sanitize > build-sanitize/configure.log 2>&1 ||
    { cat build-sanitize/configure.log; exit 1; }
  nice -n 10 cmake --build --preset sanitize
  exec nice -n 10 ctest --preset sanitize --parallel "$(nproc)" "$@"
fi
scripts/setup.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" "$@"
