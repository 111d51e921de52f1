#!/usr/bin/env bash
# Installs the Debian 12 packages tagbench needs; a quick no-op when all are present.
# Idempotent: checks dpkg status first and only calls apt-get for what is missing.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  mold  # the linker (CMakeLists.txt, TAGBENCH_MOLD): make test links ~100 test programs in each tree
  libeigen3-dev
  pybind11-dev python3-dev python3-numpy python3-pil
  libopencv-dev libopencv-contrib-dev
  povray
  libbenchmark-dev libgtest-dev
  libapriltag-dev
  zlib1g-dev libzstd-dev libssl-dev
  python3 python3-matplotlib
  python3-opencv  # examples/external/aruco_detector.py, the example external detector
)
# `make fuzz` only (scripts/install-deps.sh --fuzz): clang and its runtime, which holds libFuzzer.
if [[ "${1:-}" == "--fuzz" ]]; then
  PACKAGES+=(clang libclang-rt-14-dev)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: not root and no sudo; install as root: ${missing[*]}" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
