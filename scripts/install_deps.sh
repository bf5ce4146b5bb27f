#!/usr/bin/env bash
# Installs the Debian 12 packages Quarry needs, only those missing (apt). Safe to re-run.
set -euo pipefail
packages=(
  g++ cmake ninja-build pkg-config       # compiler and build system
  libyaml-cpp-dev                        # YAML decks
  libfmt-dev                             # formatting of messages and files
  libcli11-dev                           # command line
  libpng-dev zlib1g-dev                  # PNG plots
  libgtest-dev libgmock-dev              # unit tests
  libbenchmark-dev                       # micro-benchmarks
  libmedc-dev libhdf5-openmpi-dev        # MED load export (med.h needs the OpenMPI HDF5)
  libmed-tools                           # mdump: the tests check exported MED files with it
  python3-meshio python3-h5py            # a second MED reader (meshio reads MED with h5py) for the export test
  calculix-ccx                           # ccx: the tests run the exported CalculiX decks
  libzmq3-dev                            # coupling server/client transport (quarry serve)
  python3 python3-numpy                  # the Python module (ctypes over libquarry.so) and its tests
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install_deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -q
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
