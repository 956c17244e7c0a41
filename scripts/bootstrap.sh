#!/usr/bin/env bash
# Set-up on a fresh Debian machine: installs what is missing, builds, and runs one job.
#   scripts/bootstrap.sh demo       build the tripsitter program alone (the demo preset: release, no tests, no RTL)
#                                   and render the demo scene through the whole board model
#   scripts/bootstrap.sh test       build and run the whole test suite in release, then the device's tests with its
#                                   fixed-point checks on (the check-fixed preset), then the libFuzzer targets (built
#                                   with the address and undefined-behaviour sanitizers). What CI runs (.ci/run)
#   scripts/bootstrap.sh sanitize   build and run the suite under the address+undefined sanitizers (the asan preset),
#                                   then the test executables that start threads under the thread sanitizer (tsan;
#                                   CMakePresets.json): kept green and run before every submission, apart from `test`
#                                   to keep CI within its time (README.md, "Development")
set -euo pipefail
cd "$(dirname "$0")/.."

job=${1:-demo}
case "$job" in
  demo|test|sanitize) ;;
  *) echo "usage: $0 demo|test|sanitize" >&2; exit 2 ;;
esac

packages=(g++ cmake make pkg-config libpng-dev nlohmann-json3-dev libcli11-dev libsdl2-dev libsdl2-ttf-dev
          fonts-dejavu-core libgtest-dev libbenchmark-dev
          libjs-chart.js              # explore's report inlines Chart.js
          libopenexr-dev              # render --out FILE.exr (with Imath)
          libembree-dev               # optional: bench compares primary rays with Embree
          libopenmpi-dev openmpi-bin  # optional: render --mode path under mpirun
          verilator yosys             # optional: the device's RTL (rtl/), simulated and synthesised
)
# the libFuzzer targets (scripts/fuzz.sh) and the SMT solver of the RTL's proofs (scripts/prove.sh); the headless
# browser that looks at explore's report, in every test job
[ "$job" = test ] && packages+=(clang-14 libclang-rt-14-dev z3)
[ "$job" != demo ] && packages+=(chromium)
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
  build demo
  ./build/demo/src/tripsitter/cmd/tripsitter render --scene demo --out build/demo.png
  echo "the demo frame is in $(pwd)/build/demo.png"
elif [ "$job" = sanitize ]; then
  build asan
  ctest --preset asan
  build tsan
  ctest --preset tsan
else
  # The builds the release suite does not need run beside it from the start, at nice 19: they take the processor
  # time the release job leaves (its configure runs Verilator one model at a time, on one processor) and otherwise
  # wait. Their output goes to build/<name>.log and is printed where the stage used to be; if this script stops
  # early, they are stopped with it.
  declare -A beside_pid
  device_test=""
  trap 'for p in "${beside_pid[@]}"; do kill -- -"$p" 2>/dev/null || true; done
        [ -z "$device_test" ] || kill "$device_test" 2>/dev/null || true' EXIT
  # beside NAME PRESET: configure and build PRESET at nice 19 in a process group of its own (set -m), in this
  # session: the kernel's autogroups share the processors between sessions first, so in a session of its own
  # (setsid) a nice 19 build took as much as the release build did.
  beside() {
    mkdir -p build
    set -m
    nice -n 19 bash -c 'cmake --preset "$0" >/dev/null && cmake --build --preset "$0" -j "$1"' "$2" "$jobs" \
      > "build/$1.log" 2>&1 &
    beside_pid[$1]=$!
    set +m
  }
  # finish NAME [quiet]: waits for NAME's build and prints its output (quiet: only if it failed); exit 1 if it failed.
  finish() {
    local status=0
    wait "${beside_pid[$1]}" || status=$?
    unset "beside_pid[$1]"
    if [ "$status" -ne 0 ]; then
      cat "build/$1.log"
      echo "the $1 build failed (exit $status)" >&2
      exit 1
    fi
    [ "${2:-}" = quiet ] || cat "build/$1.log"
  }
  start=$SECONDS
  beside check-fixed check-fixed
  beside fuzz-build fuzz
  build release
  echo "release build: $((SECONDS - start)) s"
  ctest --preset release
  echo "release build and suite: $((SECONDS - start)) s"
  # The release build checks no fixed-point invariant (TRIPSITTER_CHECK_FIXED follows NDEBUG): the device's tests
  # again with every check on, the build of device_test alone; run while the fuzz targets run (it is one thread),
  # its output printed after theirs.
  finish check-fixed
  finish fuzz-build quiet
  ./build/check-fixed/src/tripsitter/device/device_test --gtest_brief=1 > build/check-fixed/device_test.log 2>&1 &
  device_test=$!
  # Every fuzz target: its saved regressions, then 50,000 executions from its seed corpus (which replays
  # every seed first; receiver_pins, which simulates the receiver's RTL clock by clock, 5,000; fuzz/README.md has
  # the times), two targets at a time on two processors. Why it cannot make CI flaky:
  # - the saved regressions and the seeds are replayed as they are, every time;
  # - the search is bounded by executions, not time, with a fixed seed and a fresh working corpus, so a
  #   slow or busy machine runs the same mutations as a fast one and nothing carries over from an
  #   earlier run (libFuzzer is not bit-exact even so: repeated runs here reached the same edge coverage
  #   and differed a little in features and corpus);
  # - a crash it reports is a real bug in the code it names, never noise: the log shows the failing
  #   check, the input is saved and the command to repeat the run is printed. An unrelated change that
  #   happens to expose it still fails, as it should; fix the bug and keep the input in
  #   fuzz/regressions/ (fuzz/README.md).
  # Long, randomly seeded runs are for people: scripts/fuzz.sh SECONDS.
  fuzz_status=0
  scripts/fuzz.sh --ci 50000 || fuzz_status=$?
  device_test_status=0
  wait "$device_test" || device_test_status=$?
  device_test=""
  echo "device_test with the fixed-point checks on (build/check-fixed):"
  cat build/check-fixed/device_test.log
  echo "the whole test job: $((SECONDS - start)) s"
  [ "$device_test_status" -eq 0 ] || { echo "device_test failed (exit $device_test_status)" >&2; exit 1; }
  exit "$fuzz_status"
fi
