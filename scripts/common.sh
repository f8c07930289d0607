# Shared by scripts/demo.sh and scripts/test.sh: installs the Debian packages
# that are missing, configures and builds. Source it; it sets SYLVA_ROOT and
# SYLVA_BUILD.
set -euo pipefail

SYLVA_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SYLVA_BUILD="${SYLVA_BUILD:-$SYLVA_ROOT/build}"
SYLVA_JOBS="${SYLVA_JOBS:-$(nproc)}"

sylva_log() { printf '\n== %s\n' "$*" >&2; }

sylva_install_packages() {
  local wanted missing=()
  wanted=$(grep -v '^\s*#' "$SYLVA_ROOT/scripts/debian-packages.txt" | grep -v '^\s*$')
  for package in $wanted; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" \
      || missing+=("$package")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    sylva_log "Debian packages: all present"
    return
  fi
  sylva_log "Installing Debian packages: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
}

# sylva_build [TARGET...]: configure (Release, Ninja) and build.
sylva_build() {
  sylva_log "Configuring in $SYLVA_BUILD"
  cmake -S "$SYLVA_ROOT" -B "$SYLVA_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    ${SYLVA_CMAKE_ARGS:-} >/dev/null
  sylva_log "Building with $SYLVA_JOBS jobs"
  if [ $# -gt 0 ]; then
    cmake --build "$SYLVA_BUILD" -j "$SYLVA_JOBS" --target "$@"
  else
    cmake --build "$SYLVA_BUILD" -j "$SYLVA_JOBS"
  fi
}
