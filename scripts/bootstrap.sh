#!/usr/bin/env bash
# Set-up on a fresh Debian machine: installs what is missing, builds, and runs one job.
#   scripts/bootstrap.sh demo   build (release) and render the demo scene through the whole board model
#   scripts/bootstrap.sh test   build and run the whole test suite: release, then under the address+undefined
#                               sanitizers, then under the thread sanitizer
set -euo pipefail
cd "$(dirname "$0")/.."

job=${1:-demo}
case "$job" in
  demo|test) ;;
  *) echo "usage: $0 demo|test" >&2; exit 2 ;;
esac

packages=(g++ cmake make pkg-config libpng-dev nlohmann-json3-dev libcli11-dev libsdl2-dev libsdl2-ttf-dev
          fonts-dejavu-core libgtest-dev libbenchmark-dev
          libembree-dev               # optional: bench compares primary rays with Embree
          libopenmpi-dev openmpi-bin  # optional: render --mpi across ranks
          clang-14 libclang-rt-14-dev # test job: the libFuzzer targets
)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi

jobs=$(nproc)
build() {
  cmake --preset "$1" >/dev/null
  cmake --build --preset "$1" -j "$jobs"
}

if [ "$job" = demo ]; then
  build release
  ./build/release/src/tripsitter/cmd/tripsitter render --scene demo --out build/demo.png
  echo "the demo frame is in $(pwd)/build/demo.png"
else
  build release
  ctest --preset release
  build asan
  ctest --preset asan
  build tsan
  ctest --preset tsan
fi
