#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds everything (tests
# and benchmarks included) and runs CTest. Extra arguments go to ctest, e.g.
#   scripts/test.sh -L fidelity        scripts/test.sh -R cli
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
sylva_install_packages
sylva_build
sylva_log "Running the tests"
cd "$SYLVA_BUILD"
ctest --output-on-failure -j "$SYLVA_JOBS" "$@"
