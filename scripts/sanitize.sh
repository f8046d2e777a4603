#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build of the unit and verification tests
# (issue 17, item 6), in its own build directory (default build-asan/). Any sanitizer report
# fails the run (UBSan does not recover). PETSc/MPI and the Python module are left out (MPI
# and CPython have reports of their own that are not ours). Leak detection is off: Gmsh's
# global state is never freed.
# Usage: scripts/sanitize.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build-asan}"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSIGNORINI_WITH_PETSC=OFF \
  -DSIGNORINI_BUILD_PYTHON=OFF -DSIGNORINI_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j "$(nproc)" --target signorini unit_tests verification_tests
export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# A larger stack: AddressSanitizer gives every temporary its own stack slot, and the 3D mortar's
# hyper-dual numbers over up to 52 coordinates (21 kB each) overflowed the default 8 MB in
# Mortar3d.* on quadratic slave facets (the plain build runs them in 8 MB).
ulimit -s 65536 2>/dev/null || true
cd "$build" && ctest -L 'unit|verification' -E "${SANITIZE_EXCLUDE:-^$}" -j "$(nproc)" --output-on-failure --timeout 1800
