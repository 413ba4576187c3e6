#!/usr/bin/env bash
# One command from a fresh Debian 12 machine (as root or with sudo):
#   scripts/setup.sh demo   installs what is needed, builds, runs `isg run` on samples/contact
#   scripts/setup.sh test   installs what is needed, builds, runs the whole test suite (ctest)
#   scripts/setup.sh bench  installs what is needed, builds, regenerates docs/benchmark* (bench/bench.py)
set -euo pipefail
mode=${1:-demo}
case "$mode" in demo|test|bench) ;; *) echo "usage: $0 demo|test|bench" >&2; exit 2 ;; esac
cd "$(dirname "$0")/.."

# Debian 12 packages only; nothing vendored.
pkgs=(cmake ninja-build g++ pkg-config
      libopenimageio-dev libopenexr-dev
      libopencolorio-dev libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools
      libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libgtest-dev)
# The test suite also builds the libFuzzer harnesses with clang, starts a one-node Slurm cluster
# for `isg farm` (slurm-wlm, munge; tests/farm) and builds and tests the Python module (pybind11,
# NumPy and pytest for Debian's python3; tests/python).
[ "$mode" = test ] && pkgs+=(clang libclang-rt-14-dev slurm-wlm munge
                            python3 python3-dev pybind11-dev python3-numpy python3-pytest)
# The benchmark drives isg from Python and edits EXRs with oiiotool.
[ "$mode" = bench ] && pkgs+=(python3 openimageio-tools)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build=${ISG_BUILD_DIR:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" --parallel "$(nproc)"

if [ "$mode" = demo ]; then
  mkdir -p out
  "$build/cli/isg" run --scene samples/contact/scene.json samples/contact/aovs.exr \
    -o out/contact.exr --timings
  echo "output: $(realpath out/contact.exr)"
elif [ "$mode" = bench ]; then
  python3 bench/bench.py --build "$build"
else
  # XDG_RUNTIME_DIR silences a harmless loader warning on headless machines.
  export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}
  ctest --test-dir "$build" --output-on-failure --parallel "$(nproc)" --timeout 900
fi
