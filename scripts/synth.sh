#!/usr/bin/env bash
# What the device's RTL takes of the board's FPGA, the Artix-7 XC7A100T: Yosys's synth_xilinx (family xc7) of the
# top, ts_device (rtl/device/ts_device.sv), with N workers and with one, and from the two the largest N that fits.
#
#   scripts/synth.sh N [wide|board-2023]     (default board-2023)
#
# Prints LUTs (as logic and as memory), flip-flops, DSP48E1 slices and block RAMs (36 Kbit; two RAMB18 count as
# one) against the XC7A100T's 63,400 LUTs, 126,800 flip-flops, 240 DSP48E1 and 135 RAMB36. The largest N assumes
# each worker adds what the N-th added on average (workers are identical; scene memory grows by a replica per
# pair of workers). Yosys gives no timing for this family: docs/rtl.md says what sets the longest paths.
# Needs yosys (Debian: yosys). The logs are kept in build/synth/.
set -euo pipefail
cd "$(dirname "$0")/.."

n=${1:-}
preset=${2:-board-2023}
if ! [[ "$n" =~ ^[1-9][0-9]*$ ]] || ((n > 640)); then
  echo "usage: $0 N [wide|board-2023]   (N: workers, 1..640)" >&2
  exit 2
fi
case "$preset" in
  wide)       params="FRAC=4 X_W=24 Y_W=24 Z_W=24 R_W=24 MAX_SPHERES=4096 WIRE=3 SQRT_ITERATIONS=16 PIPELINED=1
                      MAX_BOUNCES=3 LEAD_CYCLES=3200 SQRT_CYCLES_PER_ITERATION=1" ;;
  board-2023) params="FRAC=3 X_W=16 Y_W=15 Z_W=15 R_W=16 MAX_SPHERES=64 WIRE=2 SQRT_ITERATIONS=16 PIPELINED=0
                      MAX_BOUNCES=0 LEAD_CYCLES=3000 SQRT_CYCLES_PER_ITERATION=2" ;;
  *) echo "$0: unknown preset '$preset' (wide or board-2023)" >&2; exit 2 ;;
esac
command -v yosys >/dev/null || { echo "$0: yosys not found (Debian: apt-get install yosys)" >&2; exit 1; }

out=build/synth
mkdir -p "$out"
sources=$(echo rtl/*/ts_*.sv)

# synth WORKERS: runs Yosys; its statistics go to $out/PRESET-nWORKERS.stat.
synth() {
  local workers=$1 log="$out/$preset-n$1.log" sets=""
  for p in $params N=$workers; do sets+=" -set ${p%%=*} ${p#*=}"; done
  if ! yosys -q -l "$log" -p "read_verilog -sv $sources; chparam$sets ts_device; synth_xilinx -family xc7 -top ts_device; tee -o $out/$preset-n$workers.stat stat" >/dev/null 2>&1; then
    echo "$0: yosys failed on $workers workers; the end of its log ($log):" >&2
    tail -n 20 "$log" >&2
    exit 1
  fi
}

# count WORKERS: "luts lutram ffs dsps brams" of that run (brams in RAMB36 units, a RAMB18 half of one). Yosys
# prints each module, then (when there are several) the whole design's totals: those count, not the sum.
count() {
  awk '
    /=== design hierarchy ===/ { lut = ram = ff = dsp = bram = 0 }
    $1 ~ /^LUT[1-6]$/ { lut += $2 }
    $1 ~ /^(RAM32M|RAM64M)$/ { ram += 4 * $2 }
    $1 ~ /^(RAM32X1D|RAM64X1D)$/ { ram += 2 * $2 }
    $1 ~ /^(RAM32X1S|RAM64X1S|RAM128X1S)$/ { ram += $2 }
    $1 ~ /^(RAM128X1D)$/ { ram += 4 * $2 }
    $1 ~ /^(FDRE|FDSE|FDCE|FDPE)$/ { ff += $2 }
    $1 == "DSP48E1" { dsp += $2 }
    $1 == "RAMB36E1" { bram += $2 }
    $1 == "RAMB18E1" { bram += $2 / 2 }
    END { printf "%d %d %d %d %.1f\n", lut, ram, ff, dsp, bram }' "$out/$preset-n$1.stat"
}

echo "synthesising ts_device ($preset) with $n workers and with 1 (yosys synth_xilinx -family xc7; logs in $out/) ..." >&2
synth "$n"
read -r lut ram ff dsp bram <<<"$(count "$n")"
if ((n > 1)); then
  synth 1
  read -r lut1 ram1 ff1 dsp1 bram1 <<<"$(count 1)"
else
  lut1=$lut ram1=$ram ff1=$ff dsp1=$dsp bram1=$bram
fi

awk -v n="$n" -v preset="$preset" \
    -v lut="$lut" -v ram="$ram" -v ff="$ff" -v dsp="$dsp" -v bram="$bram" \
    -v lut1="$lut1" -v ram1="$ram1" -v ff1="$ff1" -v dsp1="$dsp1" -v bram1="$bram1" 'BEGIN {
  printf "ts_device, %s, %d workers, on the XC7A100T:\n", preset, n
  printf "  %-24s %10s %10s %6s\n", "", "used", "of", "share"
  row("LUTs (logic + memory)", lut + ram, 63400)
  row("  of them as memory", ram, 63400)
  row("flip-flops", ff, 126800)
  row("DSP48E1", dsp, 240)
  row("block RAM (36 Kbit)", bram, 135)
  if (n == 1) { print "  (give N > 1 for the largest N that fits)"; exit }
  best = 640; limit = ""
  fit("LUTs", lut + ram, lut1 + ram1, 63400)
  fit("flip-flops", ff, ff1, 126800)
  fit("DSP48E1", dsp, dsp1, 240)
  fit("block RAM", bram, bram1, 135)
  if (best < 1) printf "  not even one worker fits (%s)\n", limit
  else printf "  largest N that fits: %d (each worker adds its share of the N-th; the limit is %s)\n", best, limit
}
function row(name, used, of) { printf "  %-24s %10.1f %10d %5.1f%%\n", name, used, of, 100 * used / of }
function fit(name, at_n, at_1, cap,    per, most) {
  per = (at_n - at_1) / (n - 1)
  if (per <= 0) return
  most = 1 + int((cap - at_1) / per)
  if (most < best) { best = most; limit = name }
}'
