#!/usr/bin/env bash
# README command 2: install what is missing, build and run the whole test suite — once
# optimised with assertions and warnings as errors, once under AddressSanitizer+UBSan.
# SKIP_ASAN=1 skips the sanitizer pass (for quick local runs; CI always runs it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset test >/dev/null
cmake --build --preset test
ctest --preset test
if [ "${SKIP_ASAN:-0}" != 1 ]; then
  cmake --preset debug-asan >/dev/null
  cmake --build --preset debug-asan
  ctest --preset debug-asan
fi
