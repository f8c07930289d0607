#!/usr/bin/env bash
# Fuzzes every reader (fuzz/, issue 16) with libFuzzer under AddressSanitizer
# and UndefinedBehaviorSanitizer: installs clang, builds the fuzz targets
# with clang in build-fuzz/ and runs each for SECONDS (default 60) on its
# corpus (build-fuzz/corpus/<target>/, seeded from fuzz/seeds.txt and grown
# by every run), or for N executions with --runs N. A finding stops the
# script with the target's report and the input that triggered it in
# build-fuzz/findings/; each target's statistics are in findings/<target>.log.
#   scripts/fuzz.sh [SECONDS | --runs N] [TARGET...]
#   e.g. scripts/fuzz.sh 600 mtg;  scripts/fuzz.sh --runs 1000000 manifest
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
if [ "${1:-}" = --runs ]; then
  limit=(-runs="${2:?--runs needs a number}")
  what="$2 executions"
  shift 2
else
  limit=(-max_total_time="${1:-60}")
  what="${1:-60} s"
  shift || true
fi
sylva_install_packages
FUZZ_BUILD="$SYLVA_ROOT/build-fuzz"
sylva_log "Configuring the fuzz targets (clang) in $FUZZ_BUILD"
# OSS-Fuzz's flags: -O1 and line tables only (stack traces keep their
# lines; the test suite builds these targets on every run: 10 minutes on 2
# cores from a fresh clone).
CC=clang CXX=clang++ cmake -S "$SYLVA_ROOT" -B "$FUZZ_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DSYLVA_BUILD_TESTS=OFF -DSYLVA_BUILD_FUZZERS=ON ${SYLVA_CMAKE_ARGS:-} >/dev/null

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=($(grep -v '^\s*#' "$SYLVA_ROOT/fuzz/seeds.txt" | awk 'NF { print $1 }'))
fi
sylva_log "Building ${#targets[@]} fuzz targets with $SYLVA_JOBS jobs"
cmake --build "$FUZZ_BUILD" -j "$SYLVA_JOBS" --target $(printf '%s_fuzzer ' "${targets[@]}")

mkdir -p "$FUZZ_BUILD/findings"
# A small quarantine: the readers allocate and free whole files per input,
# and a large quarantine turns that into page faults (2x the time per input).
# Allocations past 2 GB fail (malloc returns null; the .vdb target's
# operator new then throws std::bad_alloc as the C++ library does,
# fuzz/throwing_new.h) instead of being reported by libFuzzer's 4 GB limit:
# a damaged size field is then an error the reader must handle.
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1:max_allocation_size_mb=2048:quarantine_size_mb=16"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# The inputs are written to files the readers open (fuzz/fuzz_util.h): on a
# memory file system when there is one (a disk costs ~1 ms of system time
# per input).
if [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
for target in "${targets[@]}"; do
  corpus="$FUZZ_BUILD/corpus/$target"
  mkdir -p "$corpus"
  for seed in $(awk -v t="$target" '$1 == t { for (i = 2; i <= NF; ++i) print $i }' \
      "$SYLVA_ROOT/fuzz/seeds.txt"); do
    if [ -d "$SYLVA_ROOT/$seed" ]; then cp -n "$SYLVA_ROOT/$seed"/* "$corpus/"; else
      cp -n "$SYLVA_ROOT/$seed" "$corpus/"; fi
  done
  sylva_log "Fuzzing $target for $what ($(ls "$corpus" | wc -l) inputs in its corpus)"
  set +e
  LSAN_OPTIONS="suppressions=$SYLVA_ROOT/cmake/lsan.supp:fast_unwind_on_malloc=1" \
  "$FUZZ_BUILD/fuzz/${target}_fuzzer" "$corpus" "${limit[@]}" \
    -max_len=65536 -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$FUZZ_BUILD/findings/${target}-" > "$FUZZ_BUILD/findings/${target}.log" 2>&1
  status=$?
  set -e
  tail -n 8 "$FUZZ_BUILD/findings/${target}.log"
  if [ "$status" -ne 0 ]; then
    grep -A 30 "ERROR\|runtime error\|deadly signal" "$FUZZ_BUILD/findings/${target}.log" | head -n 40
    sylva_log "FINDING in $target (exit $status): see $FUZZ_BUILD/findings/"
    exit 1
  fi
done
sylva_log "No finding in ${#targets[@]} targets, $what each"
