#!/usr/bin/env bash
# Install granule's build dependencies from Debian packages and build it (release, in build/).
# Run as root on a fresh Debian 12 machine; safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential meson ninja-build pkg-config git
          libgsl-dev libsundials-dev check libinih-dev libcjson-dev librandom123-dev
          libfftw3-dev libcairo2-dev gnuplot-nox zlib1g-dev
          libopenmpi-dev openmpi-bin # MPI: granule sweep over ranks (docs/cluster.md)
          clang libclang-rt-dev # libFuzzer + sanitizers: scripts/fuzz.sh (docs/fuzzing.md)
          clang-format # the layout of every C file (.clang-format, scripts/format.sh)
          python3-dev python3-numpy python3-pandas python3-matplotlib # import granule (docs/python.md)
          python3-mesonpy python3-venv # pip install . of the module, tested in a venv (docs/python.md)
          lammps # the LAMMPS bridge and its test (docs/lammps.md)
          libhdf5-dev # H5MD trajectories (docs/trajectories.md)
          # readers the suite runs on our outputs with Debian's /usr/bin/python3 (docs/trajectories.md)
          python3-ase python3-mdanalysis python3-h5py)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >/dev/null
    apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
fi

if [[ ! -f build/build.ninja ]]; then
    meson setup build --buildtype=release >/dev/null
fi
ninja -C build >/dev/null
echo "setup: built build/granule" >&2
