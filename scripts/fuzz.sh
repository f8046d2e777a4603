#!/usr/bin/env bash
# libFuzzer campaign on the input readers (issue 17, item 6): the YAML deck reader, the Gmsh
# .msh reader and the CalculiX/Abaqus .inp reader, built with clang and
# -fsanitize=fuzzer,address,undefined in their own build directory (default build-fuzz/).
# Each target runs SECONDS seconds from its seeds (fuzz/corpus/<kind>, plus the shipped
# example decks and the CalculiX harness decks); a crash, a sanitizer report, a leak, an
# exception other than an InputError, an input taking more than 10 s or 2 GB fails the run
# (leaks inside Debian's libgmsh are suppressed: fuzz/lsan.supp)
# and leaves the input under build-fuzz/artifacts/<target>/. The corpus grows in
# build-fuzz/corpus/<target>/ from run to run.
# Usage: scripts/fuzz.sh SECONDS [fuzz_deck fuzz_msh fuzz_inp]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
secs="${1:?usage: scripts/fuzz.sh SECONDS [TARGET...]}"
shift
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_deck fuzz_msh fuzz_inp)
build="${FUZZ_BUILD:-$here/build-fuzz}"

bash "$here/scripts/install-deps.sh"
if ! command -v clang++ >/dev/null || ! [ -e "$(clang++ -print-file-name=libclang_rt.fuzzer-x86_64.a)" ] ||
   ! [ -e /usr/lib/llvm-14/lib/libomp.so ]; then
  ${SUDO:-$( [ "$(id -u)" = 0 ] || echo sudo )} apt-get install -y clang libclang-rt-14-dev libomp-14-dev
fi
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS="$flags" \
  -DSIGNORINI_BUILD_FUZZERS=ON -DSIGNORINI_BUILD_TESTS=OFF -DSIGNORINI_BUILD_BENCH=OFF \
  -DSIGNORINI_WITH_PETSC=OFF -DSIGNORINI_BUILD_PYTHON=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

kind() { echo "${1#fuzz_}"; }
status=0
for t in "${targets[@]}"; do
  k="$(kind "$t")"
  corpus="$build/corpus/$t" seeds="$build/seeds/$t" artifacts="$build/artifacts/$t"
  rm -rf "$artifacts"  # a finding of an earlier run is in its log; this run starts clean
  mkdir -p "$corpus" "$seeds" "$artifacts"
  cp "$here/fuzz/corpus/$k/"* "$seeds/"
  case "$k" in
    deck) for f in "$here"/examples/*/*.yaml; do cp "$f" "$seeds/"; done ;;
    msh) find "$here/tests" "$here/examples" -name '*.msh' -size -2M -exec cp {} "$seeds/" \; ;;
    inp) for f in "$here"/tests/data/calculix/runs/*/job.inp; do cp "$f" "$seeds/$(basename "$(dirname "$f")").inp"; done ;;
  esac
  echo "== $t: $secs s (seeds: $(ls "$seeds" | wc -l), corpus: $(ls "$corpus" | wc -l))"
  set +e
  ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
  LSAN_OPTIONS="suppressions=$here/fuzz/lsan.supp:print_suppressions=0" \
    "$build/fuzz/$t" "$corpus" "$seeds" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$artifacts/" -print_final_stats=1 >"$build/$t.log" 2>&1
  rc=$?
  set -e
  grep -E "^stat::(number_of_executed_units|peak_rss_mb)|^#[0-9]+ +DONE" "$build/$t.log" | tail -3 || true
  if [ $rc -ne 0 ] || [ -n "$(ls -A "$artifacts")" ]; then
    echo "FINDING in $t (exit $rc): $(ls "$artifacts" | head -5); the log: $build/$t.log"
    grep -E "ERROR|finding|SUMMARY|runtime error" "$build/$t.log" | head -5 || true
    status=1
  fi
done
exit $status
