#!/usr/bin/env bash
# Installs stickslip's build and run dependencies from Debian's packages. Idempotent: returns at once when
# everything is already there. `--bench-getfem` adds GetFEM's Python module for the side-by-side Hertz benchmark
# (tests/bench/hertz/bench_getfem.py); no test needs it.
set -euo pipefail
packages=(build-essential cmake pkg-config trilinos-all-dev libptscotch-dev libmetis-dev libopenmpi-dev openmpi-bin
          gmsh libgmsh-dev libyaml-dev gnuplot-nox python3 python3-yaml)
if [ "${1:-}" = "--bench-getfem" ]; then
  packages+=(python3-getfem python3-scipy)
elif [ $# -gt 0 ]; then
  echo "usage: scripts/install-deps.sh [--bench-getfem]" >&2
  exit 2
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
