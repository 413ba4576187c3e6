#!/usr/bin/env bash
# One command from a fresh Debian 12 machine (as root or with sudo):
#   scripts/setup.sh demo   installs what is needed, builds, runs `isg run` on samples/contact
#   scripts/setup.sh test   installs what is needed, builds, runs the whole test suite (ctest)
#   scripts/setup.sh bench  installs what is needed, builds, regenerates docs/benchmark* (bench/bench.py)
#   scripts/setup.sh cases  also installs Blender, renders the repository's own Cycles cases that are
#                           missing (tools/cases, into $ISG_OWN_CASES, default ../cases-own; about 20
#                           minutes each on 2 cores) and the moved copies of shared contact, checks
#                           them and runs bench/shadow_cases.py
set -euo pipefail
mode=${1:-demo}
case "$mode" in demo|test|bench|cases) ;; *) echo "usage: $0 demo|test|bench|cases" >&2; exit 2 ;; esac
cd "$(dirname "$0")/.."

# Debian 12 packages only; nothing vendored.
pkgs=(cmake ninja-build g++ pkg-config help2man dpkg-dev man-db
      libopenimageio-dev libopenexr-dev
      libopencolorio-dev libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools
      libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libgtest-dev)
# The test suite also builds the libFuzzer harnesses with clang, runs clang-tidy, starts a one-node Slurm cluster
# for `isg farm` (slurm-wlm, munge; tests/farm) and builds and tests the Python module (pybind11,
# NumPy and pytest for Debian's python3; tests/python).
[ "$mode" = test ] && pkgs+=(clang libclang-rt-14-dev clang-tidy slurm-wlm munge
                            python3 python3-dev pybind11-dev python3-numpy python3-pytest)
# The benchmark drives isg from Python and edits EXRs with oiiotool.
[ "$mode" = bench ] && pkgs+=(python3 openimageio-tools)
# The Cycles case generator (../shared/tools/cases, wrapped by tools/cases) runs Blender 3.4.
[ "$mode" = cases ] && pkgs+=(python3 openimageio-tools blender python3-openimageio python3-numpy)
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
elif [ "$mode" = cases ]; then
  own=${ISG_OWN_CASES:-$(cd .. && pwd)/cases-own}
  for c in $(tools/cases/make_cases.sh --own); do
    [ -f "$own/$c/ref/softshadow_key.exr" ] || tools/cases/make_cases.sh "$c" "$own"
  done
  # the shared contact case moved after rendering: only P's precision changes (tools/cases/README.md)
  for e in 5 6; do
    [ -f "$own/contact-moved1e$e/aovs.exr" ] ||
      /usr/bin/python3 tools/cases/translate_case.py ../shared/cases/contact "$own/contact-moved1e$e" 1e$e
  done
  /usr/bin/python3 "${ISG_CASES_SHARED_TOOLS:-../shared/tools/cases}/check_case.py" "$own"/*/ ||
    echo "check_case.py: the far cases and grazing fail some checks by design (tools/cases/README.md)"
  ISG_OWN_CASES=$own python3 bench/shadow_cases.py --build "$build"
else
  # The libFuzzer harnesses are built here, with the rest of the build (clang, sanitizers: two
  # minutes on two cores); ctest's fuzz_build then finds them built and the smoke runs use them.
  command -v clang++ >/dev/null && ISG_FUZZ_BUILD_DIR="$build/fuzz" ISG_BUILD_DIR="$build" scripts/fuzz.sh 0
  # XDG_RUNTIME_DIR silences a harmless loader warning on headless machines.
  export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}
  ctest --test-dir "$build" --output-on-failure --parallel "$(nproc)" --timeout 900
fi
