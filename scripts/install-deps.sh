#!/usr/bin/env bash
# Install the Debian packages demsa needs, only those that are missing.
# Idempotent; runs as root or through sudo; says what it installs; fails loudly.
#
#   scripts/install-deps.sh            build, run and test dependencies
#   scripts/install-deps.sh --slurm    also the packages of a local SLURM (tests of the slurm executor)
#   scripts/install-deps.sh --liggghts-build  also what scripts/build-liggghts.sh needs (ccache, xz-utils)
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  liggghts libliggghts-dev libopenmpi-dev openmpi-bin
  libeigen3-dev libgsl-dev libnlopt-cxx-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
  libsqlite3-dev libsqlitecpp-dev sqlite3 libfmt-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox python3-numpy python3-scipy clang-format
  python3-vtk9
)
for option in "$@"; do
  case $option in
    --slurm) packages+=(slurmctld slurmd slurm-client munge) ;;
    --liggghts-build) packages+=(ccache xz-utils) ;;
    *) echo "install-deps: error: unknown option '$option' (--slurm, --liggghts-build)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=()
if [[ $(id -u) != 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: error: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  SUDO=(sudo)
fi

echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq -o DPkg::Lock::Timeout=300
"${SUDO[@]}" apt-get install -y -qq -o DPkg::Lock::Timeout=300 --no-install-recommends "${missing[@]}" \
  || { echo "install-deps: error: apt-get install failed for: ${missing[*]}" >&2; exit 1; }

# Verify: every package must now be installed.
still=()
for p in "${missing[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || still+=("$p")
done
if ((${#still[@]})); then
  echo "install-deps: error: still missing after install: ${still[*]}" >&2
  exit 1
fi
echo "install-deps: done"
