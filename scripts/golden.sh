#!/usr/bin/env bash
# The fixed set of outputs that a change of structure must leave bit for bit as they are: hw frames of every
# built-in scene and a scene file under both wires and both presets, what render prints about them, the float
# reference and the path tracer at two sizes each (both samplers, and denoised), 4-frame animations in every
# mode, a VCD trace, encoded link bytes on every wire (v3 with a fixed session), the device fed those bytes, and a
# decoded v3 stream.
#
#   scripts/golden.sh BIN                  prints "sha256  name" for every output of the set (to record them)
#   scripts/golden.sh BIN --check FILE     renders the set and compares it with FILE; exit 1 on any difference
#
# BIN is a built tripsitter. The outputs are written to a temporary directory, removed at the end. Timings are
# not part of the set: the path tracer runs with --quiet.
set -euo pipefail

bin=$(realpath "${1:?usage: $0 BIN [--check FILE]}")
check=""
if [ "${2:-}" = --check ]; then check=$(realpath "${3:?--check needs a file}"); fi
root=$(cd "$(dirname "$0")/.." && pwd)
scene_file="$root/scenes/three_materials.json"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cd "$out"

# run NAME ARGS...: a command whose stdout and stderr are part of the set (as NAME.out and NAME.err).
run() {
  local name=$1
  shift
  "$bin" "$@" >"$name.out" 2>"$name.err"
}

for scene in demo cluster field "$scene_file"; do
  tag=$(basename "$scene" .json)
  for wire in v1 v2; do
    for preset in wide board-2023; do
      run "hw-$tag-$wire-$preset" render --scene "$scene" --wire "$wire" --preset "$preset" \
          --out "hw-$tag-$wire-$preset.png"
    done
  done
  run "compare-$tag" render --scene "$scene" --compare --workers 640 --out "compare-$tag.png"
done
run vcd render --scene demo --vcd vga.vcd --lines 600 --out vcd.png

run normal-field render --scene field --mode normal --width 640 --height 480 --out normal-field.png
run normal-cluster render --scene cluster --mode normal --width 317 --height 203 --bounces 0 --out normal-cluster.png
# The independent sampler keeps the bytes it had before the Sobol sampler became the default.
run path-field render --scene field --mode path --width 160 --height 90 --spp 4 --threads 2 --quiet --out path-field.png \
    --sampler independent
run path-three render --scene "$scene_file" --mode path --width 97 --height 61 --spp 8 --depth 6 --seed 7 --quiet \
    --out path-three.png --sampler independent
run path-field-sobol render --scene field --mode path --width 160 --height 90 --spp 4 --threads 2 --quiet \
    --out path-field-sobol.png
run path-field-denoised render --scene field --mode path --width 160 --height 90 --spp 4 --threads 2 --quiet \
    --denoise --out path-field-denoised.png

mkdir hw-anim normal-anim path-anim
run anim-hw render --scene cluster --frames 4 --orbit 90 --out hw-anim/f_%02d.png --quiet
run anim-normal render --scene field --mode normal --width 200 --height 150 --frames 4 --orbit -60 \
    --out normal-anim/f_%02d.png --quiet
run anim-path render --scene cluster --mode path --width 80 --height 60 --spp 2 --frames 4 --orbit 120 \
    --out path-anim/f_%02d.png --quiet --sampler independent

for wire in v1 v2 v3; do
  session=()
  [ "$wire" = v3 ] && session=(--session 7)  # a host draws its session at random; fixed here
  "$bin" link encode --scene cluster --wire "$wire" "${session[@]}" >"link-cluster-$wire.bin" 2>"link-cluster-$wire.err"
  run "link-input-$wire" render --link-input "link-cluster-$wire.bin" --wire "$wire" --out "link-input-$wire.png"
done
"$bin" link encode --scene cluster --wire v3 --session 7 --worlds 5 --orbit 40 >link-orbit-v3.bin 2>link-orbit-v3.err
"$bin" link decode --wire v3 --json --in link-orbit-v3.bin >link-decode-v3.json 2>link-decode-v3.err

# Outputs that name the temporary directory would differ from run to run: those lines name it as $OUT.
find . -type f -name '*.err' -exec sed -i "s|$out|\$OUT|g" {} +
find . -type f ! -name '*.sums' -printf '%P\n' | LC_ALL=C sort | xargs sha256sum >"$out/all.sums"

if [ -z "$check" ]; then
  cat all.sums
  exit 0
fi
if diff -u "$check" all.sums; then
  echo "golden: $(wc -l <all.sums) outputs identical to $check"
else
  echo "golden: outputs differ from $check (lines marked - are the recorded sums, + this build's)" >&2
  exit 1
fi
