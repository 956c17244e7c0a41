#!/usr/bin/env bash
# Regenerates the seed corpora of fuzz/corpus/ from real encoded worlds (tripsitter link encode), the
# repository's scenes and a few key scripts. Deterministic: running it again gives the same files.
#   fuzz/make_corpus.sh [path/to/tripsitter]     (default: build/fuzz's, else build/release's)
set -euo pipefail
cd "$(dirname "$0")/.."

bin=${1:-}
if [ -z "$bin" ]; then
  for b in build/fuzz/src/tripsitter/cmd/tripsitter build/release/src/tripsitter/cmd/tripsitter; do
    [ -x "$b" ] && { bin=$b; break; }
  done
fi
[ -n "$bin" ] && [ -x "$bin" ] || { echo "no tripsitter binary: build one, or pass its path" >&2; exit 2; }
export ASAN_OPTIONS=detect_leaks=0   # a sanitizer build of the command is fine here

out=fuzz/corpus
mkdir -p "$out"/{wire_v1,wire_v2,wire_v3,receiver,receiver_pins,scene_json,key_script}
# Inputs found by fuzzing and merged in (fuzz/README.md) are named by their SHA-1 and stay; the named seeds
# are made again.
find "$out" -regextype posix-extended -type f ! -regex '.*/[0-9a-f]{40}' -delete
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# encode SCENE PRESET WIRE [ARGS...]: the host's bytes for one world (more with --worlds), numbered as the link
# numbers them; on v3 in session 1 unless ARGS say otherwise, so that the seeds are the same every time.
encode() {
  local scene=$1 preset=$2 wire=$3
  shift 3
  [ "$wire" = v3 ] && [[ " $* " != *" --session "* ]] && set -- --session 1 "$@"
  "$bin" link encode --scene "$scene" --preset "$preset" --wire "$wire" "$@" 2>/dev/null
}
# bytes HEX...: raw bytes from hex pairs.
bytes() { printf '%s' "$*" | xxd -r -p; }
# tag NAME: a file-name-safe name for a scene.
tag() { basename "$1" .json; }

printf '{"spheres": []}' > "$tmp/empty.json"
scenes=(demo cluster field random-3 random-60 scenes/three_materials.json "$tmp/empty.json")
for s in "${scenes[@]}"; do
  for preset in wide board-2023; do
    encode "$s" "$preset" v2 > "$tmp/$(tag "$s")-$preset.v2"
    encode "$s" "$preset" v3 > "$tmp/$(tag "$s")-$preset.v3"
    encode "$s" "$preset" v1 > "$tmp/$(tag "$s")-$preset.v1"
  done
done
# field has 488 spheres (11.7 KB as a frame, more than the stream decoder's 4 KB slice): it seeds only the
# receiver, whose input may be that long; the other seeds stay small, so the fuzzers stay fast.

# wire_v2: whole frames, and streams of frames with damage between them.
for f in "$tmp"/*.v2; do cp "$f" "$out/wire_v2/$(basename "$f" .v2)"; done
cat "$tmp/demo-wide.v2" "$tmp/cluster-wide.v2" > "$out/wire_v2/stream-two-frames"
{ bytes 0001545357; cat "$tmp/demo-wide.v2"; } > "$out/wire_v2/stream-garbage-then-frame"
head -c 100 "$tmp/cluster-wide.v2" > "$out/wire_v2/stream-truncated"
{ head -c 30 "$tmp/cluster-wide.v2"; cat "$tmp/three_materials-wide.v2"; } > "$out/wire_v2/stream-frame-inside-damaged"
bytes 5453573202000000000000070000000000000000 > "$out/wire_v2/empty-world-without-crc"
rm -f "$out"/wire_v2/field-* "$out"/wire_v2/random-60-board-2023

# wire_v3: a few whole frames, and streams: several worlds of an orbit, damage, a host that restarts in the
# middle of a world (its cut frame is dropped as truncated when the new frame's intact header arrives), and
# a frame with an intact header of another inside its spheres (wire_v3_fuzz.cpp: nested_headers).
for name in demo-wide cluster-wide cluster-board-2023 three_materials-wide empty-wide; do
  cp "$tmp/$name.v3" "$out/wire_v3/$name"
done
encode random-3 wide v3 --worlds 3 > "$out/wire_v3/stream-three-worlds"
{ bytes 0001545357; cat "$tmp/demo-wide.v3"; } > "$out/wire_v3/stream-garbage-then-frame"
head -c 100 "$tmp/cluster-wide.v3" > "$out/wire_v3/stream-truncated"
{ head -c 60 "$tmp/cluster-wide.v3"; encode demo wide v3 --session 2; } > "$out/wire_v3/stream-host-restarts-mid-world"
# Worlds with the hierarchy the host sends the artix path preset (content 1): 16 spheres in four leaves, and 60.
encode random-16 artix-path v3 > "$out/wire_v3/random-16-artix-path"
encode random-60 artix-path v3 > "$tmp/random-60-artix-path.v3"
bytes 545357330304000000000001000000010000000200000030904a7b855453573303040000000000020000000100000001 \
      000000185f95c5610000000000000000000001400000000000001800dfc00a36 > "$out/wire_v3/nested-intact-header"

# wire_v1: a control byte (transfer sizes, an odd one resets at a boundary), then the words.
for f in "$tmp"/*.v1; do
  name=$(basename "$f" .v1)
  case "$name" in field-*|random-60-*) continue ;; esac
  { bytes 00; cat "$f"; } > "$out/wire_v1/$name"
done
{ bytes 07; cat "$tmp/cluster-board-2023.v1"; } > "$out/wire_v1/cluster-with-reset"
{ bytes 02; cat "$tmp/demo-board-2023.v1"; bytes 0102; } > "$out/wire_v1/demo-and-partial-word"

# receiver: configuration (bit 0 v1, bit 1 board-2023, bits 2..3 unit 1/4/16/64, bit 5 v3, bit 7 artix-path), a count of transfer bytes
# (bits 0..6 length in units, bit 7 a vertical blanking after it), the transfer bytes, then the link bytes.
# receiver_seed NAME CONFIG TRANSFERS FILES...
receiver_seed() {
  local name=$1 config=$2 transfers=$3
  shift 3
  local count=$(( ${#transfers} / 2 ))
  { bytes "$config" "$(printf '%02x' "$count")" "$transfers"; cat "$@"; } > "$out/receiver/$name"
}
receiver_seed v2-demo-wide 00 "" "$tmp/demo-wide.v2"
receiver_seed v2-cluster-wide-7byte-transfers 00 07 "$tmp/cluster-wide.v2"
receiver_seed v2-cluster-board 02 "90" "$tmp/cluster-board-2023.v2"
receiver_seed v2-field-wide-1k-transfers 0c "c0" "$tmp/field-wide.v2"
receiver_seed v2-two-worlds-blanking-between 00 "3081" "$tmp/demo-wide.v2" "$tmp/three_materials-wide.v2"
receiver_seed v2-wrong-preset 00 "" "$tmp/cluster-board-2023.v2"
receiver_seed v2-two-worlds-3-and-8-byte-transfers 00 "0388" "$tmp/random-3-wide.v2" "$tmp/cluster-wide.v2"
receiver_seed v2-garbage-then-world 00 "1f" "$out/wire_v2/stream-garbage-then-frame"
receiver_seed v2-empty-world 00 "" "$tmp/empty-wide.v2"
receiver_seed v3-cluster-wide-7byte-transfers 20 07 "$tmp/cluster-wide.v3"
receiver_seed v3-cluster-board-blanking 22 "90" "$tmp/cluster-board-2023.v3"
# Worlds 1 to 3 of session 1, world 2 again (a replay), worlds 1 and 2 of session 2 (a restarted host), then
# world 3 of session 1 (a session that has ended): 104 bytes a world.
encode random-3 wide v3 --worlds 3 > "$tmp/s1.v3"
encode random-3 wide v3 --worlds 2 --session 2 > "$tmp/s2.v3"
receiver_seed v3-replays-and-a-restart 20 "3481" "$tmp/s1.v3" <(tail -c +105 "$tmp/s1.v3" | head -c 104) \
    "$tmp/s2.v3" <(tail -c 104 "$tmp/s1.v3")
receiver_seed v3-host-restarts-mid-world 20 "0a" "$out/wire_v3/stream-host-restarts-mid-world"
# The artix path preset (bit 7) takes a hierarchy; the wide preset refuses it at the header.
receiver_seed v3-random-60-artix-path a0 "90" "$tmp/random-60-artix-path.v3"
receiver_seed v3-hierarchy-to-wide 20 "" "$out/wire_v3/random-16-artix-path"
receiver_seed v1-cluster-board 03 "88" "$tmp/cluster-board-2023.v1"
receiver_seed v1-three-wide 01 "0583" "$tmp/three_materials-wide.v1"
receiver_seed v1-demo-board 03 "" "$tmp/demo-board-2023.v1"

# receiver_pins: the receiver's layout with a timing schedule between the transfer bytes and the link bytes (a count
# byte, then 2-byte records: receiver_pins_fuzz.cpp), the link bytes cut to the target's 512. Made from the other
# link targets' corpora: every receiver input (its merged ones too) as it is, with no records (the default timing:
# SCLK at clk/6, legal); the named receiver seeds again, in transfers of 7 units with a vertical blanking after
# every other one, with a mix of legal timings (slow SCLK with long gaps; MOSI one clock before the rising edge; a
# byte cut after 3 bits; SCLK pulses while chip select is high; an end of stream a quarter into a transfer) and with
# a mix of illegal ones among legal ones (configuration bit 6: half periods of 1 and 2 clocks, MOSI changing in the
# clock of the rising edge with the bit or with the next bit, chip select falling late, rising early, a 1- or 2-clock
# gap, and an end of stream in a transfer at 2 clocks a half period); and the named wire_v1,
# wire_v2 and wire_v3 seeds as the link bytes of v1, v2 and v3 (wide) in one transfer.
# pins_seed NAME CONFIG_BITS TRANSFERS RECORDS FILE: FILE in the receiver's layout, its configuration ORed with
# CONFIG_BITS, its transfer bytes replaced by TRANSFERS unless that is "-".
pins_seed() {
  local name=$1 bits=$2 transfers=$3 records=$4 f=$5
  local size config count
  size=$(stat -c %s "$f")
  ((size >= 2)) || return 0
  config=$(xxd -p -l 1 "$f")
  count=$(( 0x$(xxd -p -s 1 -l 1 "$f") % 16 ))
  ((count <= size - 2)) || count=$((size - 2))
  {
    bytes "$(printf '%02x' $(( 0x$config | 0x$bits )))"
    if [ "$transfers" = - ]; then
      head -c $((2 + count)) "$f" | tail -c +2
    else
      bytes "$(printf '%02x' $(( ${#transfers} / 2 )))" "$transfers"
    fi
    bytes "$(printf '%02x' $(( ${#records} / 4 )))" "$records"
    head -c $((2 + count + 512)) "$f" | tail -c +$((3 + count))
  } > "$out/receiver_pins/$name"
}
legal_mix=37405a20000312601280
illegal_mix=1200000012080900d200121092001218120009000980
for f in "$out"/receiver/*; do pins_seed "receiver-$(basename "$f")" 00 - "" "$f"; done
for f in "$out"/receiver/*; do
  name=$(basename "$f")
  [[ $name =~ ^[0-9a-f]{40}$ ]] && continue
  pins_seed "legal-mix-$name" 00 0787 "$legal_mix" "$f"
  pins_seed "illegal-mix-$name" 40 0787 "$illegal_mix" "$f"
done
for wire in v1 v2 v3; do
  for f in "$out"/wire_$wire/*; do
    name=$(basename "$f")
    [[ $name =~ ^[0-9a-f]{40}$ ]] && continue
    case $wire in
      v1) { bytes 0100; tail -c +2 "$f"; } > "$tmp/pins" ;;  # without wire_v1's control byte
      v2) { bytes 0000; cat "$f"; } > "$tmp/pins" ;;
      v3) { bytes 2000; cat "$f"; } > "$tmp/pins" ;;
    esac
    pins_seed "wire_$wire-$name" 00 - "" "$tmp/pins"
  done
done

# scene_json: the repository's scenes and small variants of the format.
cp scenes/*.json "$out/scene_json/"
printf '{"spheres": []}' > "$out/scene_json/minimal.json"
cat > "$out/scene_json/every-key.json" <<'JSON'
{"name": "all", "units_per_world": 32,
 "camera": {"lookfrom": [0, 1, -10], "lookat": [0, 0, 0], "vup": [0, 1, 0], "vfov": 73.739795291688,
            "defocus_angle": 0.5, "focus_dist": 10},
 "render": {"width": 640, "height": 480.0, "spp": 4, "max_depth": 8},
 "spheres": [
  {"center": [0, 0, 0], "radius": 1, "material": {"type": "lambertian", "albedo": [0.8, 0.3, 0.3]}},
  {"center": [2, 0, 0], "radius": 0.5, "material": {"type": "metal", "albedo": [0.8, 0.8, 0.8], "fuzz": 0.1}},
  {"center": [-2, 0, 0], "radius": 0.5, "material": {"type": "dielectric", "ior": 1.5}},
  {"center": [1e6, -1e6, 3e5], "radius": 1e-9}
 ]}
JSON
printf '\xef\xbb\xbf{"spheres": [{"center": [0, 0, 5], "radius": 2}], "camera": {"lookat": [0, 0, 1e-300]}}\n' \
  > "$out/scene_json/bom-and-tiny-distance.json"
printf '{"spheres": [{"center": [0, 0, 0], "radius": 1e999}]}' > "$out/scene_json/error-out-of-range.json"
printf '{\n  "camera": {"lookfrom": [0, 0, 0], "lookat": [0, 10, 0]},\n  "spheres": [\n' > "$out/scene_json/error-vup-parallel.json"
printf '{"spheres": [{"center": [0, 0, 0], "radius": 1, "material": {"type": "metal", "fuz": 0}}]}' \
  > "$out/scene_json/error-unknown-key.json"

# key_script: the documented example, the test scripts and the documented errors.
cat > "$out/key_script/docs-example" <<'KEYS'
# Walk up to the sphere, look left, step right.
W 500ms        # hold W for half a second
J 0.2s
d 100          # a bare number is milliseconds; keys in either case
wait 1s        # hold nothing for a second
L              # no duration: a tap, one tick
R              # reset world and camera
KEYS
printf '# forward, look left, step right\nW 500ms\nJ 200ms\nD 100ms\n' > "$out/key_script/forward-left-right"
printf 'W 300ms\r\nwait 60s\r\nL 300ms\r\nS 200ms\r\nQ 100ms\r\nI\r\nE 3600s\r\nk 25MS\r\ni 1ms\r\nWAIT 5ms\r\n' \
  > "$out/key_script/crlf-every-key"
printf 'a 007.50\nwait 0.0001s\n\t q\t2S # tabs\n' > "$out/key_script/decimals-and-tabs"
printf 'W 500ms\n  X 1s\n' > "$out/key_script/error-unknown-key"
printf 'W -5ms\nW 3601s\nwait\n' > "$out/key_script/error-negative"
printf 'W 500ms forward\nW500ms\nW 5min\n' > "$out/key_script/error-extra-word"

for d in "$out"/*; do echo "$(basename "$d"): $(ls "$d" | wc -l) files, $(du -sh "$d" | cut -f1)"; done
