#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds everything (tests
# and benchmarks included) and runs CTest; then builds the fuzz targets
# (clang, AddressSanitizer + UndefinedBehaviorSanitizer) and runs each
# briefly on its corpus (scripts/fuzz.sh; SYLVA_FUZZ_SECONDS each, default
# 10; 0 skips them). Extra arguments go to ctest and select tests, e.g.
#   scripts/test.sh -L fidelity        scripts/test.sh -R cli
# and then the fuzz targets do not run.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
sylva_install_packages
sylva_build
sylva_log "Running the tests"
(cd "$SYLVA_BUILD" && ctest --output-on-failure -j "$SYLVA_JOBS" "$@")
if [ $# -eq 0 ] && [ "${SYLVA_FUZZ_SECONDS:-10}" -gt 0 ]; then
  bash "$SYLVA_ROOT/scripts/fuzz.sh" "${SYLVA_FUZZ_SECONDS:-10}"
fi
