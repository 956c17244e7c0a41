#!/usr/bin/env bash
# What the device's RTL takes of the board's FPGA, the Artix-7 XC7A100T: Yosys's synth_xilinx (family xc7) of a
# preset's top as the preset configures it: ts_device (rtl/device/ts_device.sv) for wide and board-2023,
# ts_artix_device (rtl/artix/ts_artix_device.sv) for artix.
#
#   scripts/synth.sh N [PRESET]            N workers (artix: sphere units) and one (default board-2023), and from
#                                          the two the largest N that fits
#   scripts/synth.sh PRESET                the preset's whole top as it configures it (10 workers for wide and
#                                          board-2023, 9 sphere units for artix): the chip, its blocks, and its
#                                          longest paths in LUT levels (scripts/logic_depth.sh on the flattened
#                                          netlist)
#   scripts/synth.sh table [PRESET ...]    every block of each preset (default: wide, board-2023 and artix), written
#                                          to rtl/synth_table.tsv, the table src/tripsitter/device/resources_test.cpp
#                                          holds the ledger (resources.h) to; the other presets' rows are kept as
#                                          they are, each preset with the RTL version it was synthesised from
#   scripts/synth.sh arty [standalone|spi] the Arty A7-100T's board top (rtl/boards/arty_a7/ts_arty_top.sv: the artix
#                                          device with 9 sphere units) with its ROM host and the ROM image checked in
#                                          beside it (standalone, the default) or with the microcontroller's SPI on a
#                                          Pmod (spi): the chip and its blocks, the ROM host's block RAM among them
# PRESET: wide, board-2023 or artix.
#
# The chip table: LUTs (as logic and as memory: LUT RAM and shift registers), flip-flops, DSP48E1 slices and block
# RAMs (36 Kbit; two RAMB18 count as one) against the XC7A100T's 63,400 LUTs, 126,800 flip-flops, 240 DSP48E1 and
# 135 RAMB36. INV cells are not counted as LUTs (Vivado folds them into their neighbours). The largest N assumes each
# worker or unit adds what the N-th added on average (they are identical; scene memory grows by a replica per pair,
# and on artix the tile lists by a replica per pair and the per-world constants by one per unit).
#
# Sources. ts_device: the link's package first (rtl/receiver/ts_link_pkg.sv: the receiver's blocks name ts_link_pkg::X,
# so Yosys must have read it; Yosys 0.23 cannot parse `import`), then every rtl/*/ts_*.sv but rtl/artix/, rtl/path/
# (the artix path preset's blocks) and rtl/boards/. ts_artix_device: its package first (rtl/artix/ts_artix_pkg.sv,
# likewise), the other rtl/artix/ts_*.sv, rtl/common's, and the receiver's files (the link's package first) and VGA
# files it shares with ts_device (TS_ARTIX_DEVICE_SOURCES of rtl/artix/CMakeLists.txt).
#
# Blocks. synth_xilinx keeps the hierarchy (no -flatten), so Yosys synthesises every module on its own, once for all
# its instances, and the design's counts are the sum of its modules' over their instances. A block is a module with
# the modules below it that are not blocks themselves (ts_pixel_ray, ts_artix_delay and ts_artix_fifo go with the
# block that instantiates them); a block of several modules side by side in the top (artix's receiver and scanout)
# counts its instances once. ts_device's blocks:
#   receiver      ts_receiver_top, ts_receiver and its blocks (ts_rx_frame, ts_rx_sequence, ts_rx_v1_word,
#                 ts_rx_commit), ts_crc32, ts_spi_rx (the link, the frame buffer, the checks)
#   scene_memory  ts_scene_memory (two copies of the world, a replica per pair of workers)
#   scanout       ts_scanout, ts_controller, ts_line_buffers, ts_vga_timing
#   worker        ts_worker's own logic: issue, closest update, queue, colour delay, albedo products
#   sphere_test   ts_sphere_test without its square-root unit
#   sqrt_unit     ts_sqrt_unit
#   shade         ts_shade
#   reflect       ts_reflect (wide)
#   device        ts_device's own logic (the controller's least-cycles product)
# ts_artix_device's blocks:
#   receiver      ts_receiver and its blocks (ts_rx_*), ts_crc32, ts_spi_rx
#   scene_memory  ts_scene_memory (two copies of the world, a replica per pair of units)
#   scanout       ts_line_buffers, ts_vga_timing
#   unit          ts_artix_unit's own logic: the issue port, the slots, the direction banks, and its two queues
#                 (ts_artix_fifo: passes in flight, reflected rays)
#   sphere_unit   ts_artix_sphere_unit with its square root (ts_artix_isqrt) and its delays
#   shade_reflect ts_artix_shade_reflect with its delays
#   camera        ts_artix_camera (one for the device)
#   world         ts_artix_world's own logic: the queue of spheres written (ts_artix_fifo), the engine, and the
#                 per-world constants' memory (a replica per unit)
#   prepare       ts_artix_prepare (e, r^2 / 4^e, 1 / r)
#   cull          ts_artix_cull (the screen bounds)
#   tiles         ts_artix_tiles (the bounds, the builder, the lists' lengths, the lists: a replica per pair of units)
#   device        ts_artix_device's own logic (the line's windows, the directions' feed, the late pixels)
# These are the ledger's blocks (src/tripsitter/device/resources.h, rtl_blocks). The board top (arty) has the artix
# device's blocks and two of its own:
#   rom_host      ts_rom_host (standalone): the ROM image's block RAM and the SPI master that plays it
#   board         ts_arty_top's own logic, the reset (ts_reset_sync) and the buttons (ts_debounce)
# The board top is read from ts_artix_device's files (the header's "Sources") and rtl/boards/ts_*.sv and
# rtl/boards/arty_a7/ts_*.sv, with Yosys working in rtl/boards/arty_a7/, where the ROM host's $readmemh finds the
# image by its name (ts_arty_rom.mem), as Vivado does (build_bitstream.tcl's read_mem).
#
# Runs on whatever tree it sits in (rtl/ beside it). Needs yosys (Debian: yosys) and awk. Logs, statistics and
# netlists are kept in build/synth/. Times here, on 2 cores shared by several: `synth.sh board-2023` 1 min 29 s,
# `synth.sh wide` 6 min 54 s (4 min 39 s of CPU, the depth walk included), `synth.sh artix` 1 min 59 s (1 min 54 s of
# CPU), `synth.sh 12 artix` 3 min 15 s, `synth.sh table` 5 min 4 s for the three presets (4 min 55 s of CPU),
# `synth.sh arty standalone` and `synth.sh arty spi` 2 min 15 s of CPU each.
set -euo pipefail
cd "$(dirname "$0")/.."

out=build/synth
table_file=rtl/synth_table.tsv

usage() {
  echo "usage: $0 N [wide|board-2023|artix]   (N: workers or sphere units, 1..640)" >&2
  echo "       $0 wide|board-2023|artix" >&2
  echo "       $0 table [wide|board-2023|artix ...]" >&2
  echo "       $0 arty [standalone|spi]" >&2
  exit 2
}

# The preset's top, and what its N counts.
preset_top() {
  case "$1" in
    wide|board-2023) echo ts_device ;;
    artix) echo ts_artix_device ;;
    arty-standalone|arty-spi) echo ts_arty_top ;;
    *) return 1 ;;
  esac
}
preset_noun() { case "$1" in artix|arty-*) echo unit ;; *) echo worker ;; esac; }

# The top's source files, in an order Yosys can read (the header's "Sources").
preset_sources() {
  local f
  if [ "$1" = artix ]; then
    echo rtl/artix/ts_artix_pkg.sv
    for f in rtl/artix/ts_*.sv; do [ "$f" = rtl/artix/ts_artix_pkg.sv ] || echo "$f"; done
    echo rtl/receiver/ts_link_pkg.sv rtl/receiver/ts_spi_rx.sv rtl/receiver/ts_crc32.sv rtl/receiver/ts_rx_*.sv \
         rtl/receiver/ts_receiver.sv rtl/receiver/ts_scene_memory.sv
    echo rtl/vga/ts_vga_timing.sv rtl/vga/ts_line_buffers.sv rtl/common/ts_clock_gate.sv
  else
    echo rtl/receiver/ts_link_pkg.sv
    for f in rtl/*/ts_*.sv; do
      [[ "$f" == rtl/artix/* || "$f" == rtl/path/* || "$f" == rtl/boards/* || "$f" == rtl/receiver/ts_link_pkg.sv ]] ||
        echo "$f"
    done
  fi
}

# The preset's parameters of its top, as device/preset.cpp configures it (besides N: its workers or units). The
# artix top takes the preset's facts from its package; only N is set.
preset_params() {
  case "$1" in
    wide)       echo "FRAC=4 X_W=24 Y_W=24 Z_W=24 R_W=24 MAX_SPHERES=4096 WIRE=3 SQRT_ITERATIONS=16 PIPELINED=1
                      MAX_BOUNCES=3 LEAD_CYCLES=3200 SQRT_CYCLES_PER_ITERATION=1" ;;
    board-2023) echo "FRAC=3 X_W=16 Y_W=15 Z_W=15 R_W=16 MAX_SPHERES=64 WIRE=2 SQRT_ITERATIONS=16 PIPELINED=0
                      MAX_BOUNCES=0 LEAD_CYCLES=3000 SQRT_CYCLES_PER_ITERATION=2" ;;
    artix)      echo "" ;;
    *) return 1 ;;
  esac
}
preset_workers() {
  case "$1" in
    wide|board-2023) echo 10 ;;
    artix) echo 9 ;;
    *) return 1 ;;
  esac
}

# synth PRESET WORKERS [flat]: runs Yosys; the statistics go to $out/PRESET-nWORKERS.stat, and with "flat" the
# flattened netlist to $out/PRESET-nWORKERS.json (for scripts/logic_depth.sh).
synth() {
  local preset=$1 workers=$2 name="$1-n$2" sets="" json="" p top sources
  local log="$out/$name.log"
  top=$(preset_top "$preset")
  sources=$(echo $(preset_sources "$preset"))
  for p in $(preset_params "$preset") N="$workers"; do sets+=" -set ${p%%=*} ${p#*=}"; done
  [ "${3:-}" = flat ] && json="; flatten; write_json $out/$name.json"
  echo "  yosys: $top, $preset, $workers $(preset_noun "$preset")s (log: $log) ..." >&2
  if ! nice -n 10 yosys -q -l "$log" -p "read_verilog -sv $sources; chparam$sets $top;
       synth_xilinx -family xc7 -noiopad -top $top; tee -q -o $out/$name.stat stat$json" >/dev/null 2>&1; then
    echo "$0: yosys failed on $preset with $workers $(preset_noun "$preset")s; the end of its log ($log):" >&2
    tail -n 20 "$log" >&2
    exit 1
  fi
}

# synth_board MODE: the board top (standalone or spi) as ts_arty_top configures it (9 sphere units); the statistics
# go to $out/arty-MODE.stat.
synth_board() {
  local name="arty-$1" standalone=1 sources f
  [ "$1" = spi ] && standalone=0
  local log="$PWD/$out/$name.log" stat="$PWD/$out/$name.stat"
  # The artix device's files in their order, then the board's; absolute, as Yosys works in the board's folder.
  sources=$(for f in $(preset_sources artix) rtl/boards/ts_*.sv rtl/boards/arty_a7/ts_*.sv; do echo "$PWD/$f"; done)
  sources=$(echo $sources)
  echo "  yosys: ts_arty_top, $1, 9 units (log: $out/$name.log) ..." >&2
  if ! (cd rtl/boards/arty_a7 && nice -n 10 yosys -q -l "$log" -p "read_verilog -sv $sources;
        chparam -set STANDALONE $standalone ts_arty_top; synth_xilinx -family xc7 -noiopad -top ts_arty_top;
        tee -q -o $stat stat") >/dev/null 2>&1; then
    echo "$0: yosys failed on ts_arty_top ($1); the end of its log ($out/$name.log):" >&2
    tail -n 20 "$log" >&2
    exit 1
  fi
}

# count STAT: "luts lutram ffs dsps brams" of a run (brams in RAMB36 units, a RAMB18 half of one). Yosys prints
# each module, then (when there are several) the whole design's totals: those count, not the sum.
count() {
  awk '
    /=== design hierarchy ===/ { lut = ram = ff = dsp = bram = 0 }
    $1 ~ /^LUT[1-6]$/ { lut += $2 }
    $1 ~ /^(RAM32M|RAM64M|RAM128X1D)$/ { ram += 4 * $2 }
    $1 ~ /^(RAM32X1D|RAM64X1D|RAM128X1S)$/ { ram += 2 * $2 }
    $1 ~ /^(RAM32X1S|RAM64X1S|SRL16E|SRLC16E|SRLC32E)$/ { ram += $2 }
    $1 ~ /^(FDRE|FDSE|FDCE|FDPE)$/ { ff += $2 }
    $1 == "DSP48E1" { dsp += $2 }
    $1 == "RAMB36E1" { bram += $2 }
    $1 == "RAMB18E1" { bram += $2 / 2 }
    END { printf "%d %d %d %d %.1f\n", lut, ram, ff, dsp, bram }' "$1"
}

# blocks PRESET STAT: a line per block (the header's list): preset, block, instances, and per instance DSP48E1,
# LUTs (logic), LUTs as memory, flip-flops, RAMB18 (a RAMB36 is two), CARRY4. Then a line "total" of the design
# (its own counts, instances 1), which must be the sum of the blocks times their instances.
blocks() {
  awk -v preset="$1" -v top="$(preset_top "$1")" '
    function base(m) { sub(/^\$paramod\$[0-9a-f]+\\/, "", m); sub(/^\$paramod\\/, "", m); sub(/\\.*$/, "", m); return m }
    function block_of(m,    b) {
      b = base(m)
      if (b ~ /^ts_(receiver_top|receiver|rx_frame|rx_sequence|rx_v1_word|rx_commit|crc32|spi_rx)$/) return "receiver"
      if (b == "ts_scene_memory") return "scene_memory"
      if (b ~ /^ts_(scanout|controller|line_buffers|vga_timing)$/) return "scanout"
      if (b == "ts_worker") return "worker"
      if (b == "ts_sphere_test") return "sphere_test"
      if (b == "ts_sqrt_unit") return "sqrt_unit"
      if (b == "ts_shade") return "shade"
      if (b == "ts_reflect") return "reflect"
      if (b == "ts_artix_unit") return "unit"
      if (b == "ts_artix_sphere_unit") return "sphere_unit"
      if (b == "ts_artix_shade_reflect") return "shade_reflect"
      if (b == "ts_artix_camera") return "camera"
      if (b == "ts_artix_world") return "world"
      if (b == "ts_artix_prepare") return "prepare"
      if (b == "ts_artix_cull") return "cull"
      if (b == "ts_artix_tiles") return "tiles"
      if (b == "ts_device" || b == "ts_artix_device") return "device"
      if (b == "ts_rom_host") return "rom_host"
      if (b ~ /^ts_(arty_top|reset_sync|debounce)$/) return "board"
      return ""
    }
    function add(blk, type, n) {
      if (type == "DSP48E1") dsp[blk] += n
      else if (type ~ /^LUT[1-6]$/) lut[blk] += n
      else if (type ~ /^(RAM32M|RAM64M|RAM128X1D)$/) ram[blk] += 4 * n
      else if (type ~ /^(RAM32X1D|RAM64X1D|RAM128X1S)$/) ram[blk] += 2 * n
      else if (type ~ /^(RAM32X1S|RAM64X1S|SRL16E|SRLC16E|SRLC32E)$/) ram[blk] += n
      else if (type ~ /^FD[RSCP]E$/) ff[blk] += n
      else if (type == "RAMB18E1") bram[blk] += n
      else if (type == "RAMB36E1") bram[blk] += 2 * n
      else if (type == "CARRY4") carry[blk] += n
    }
    # walk(module, instances, block of the parent): its cells to its block, then its submodules. A block entered
    # through several modules side by side has as many instances as the most entered of them.
    function walk(m, times, parent,    blk, i, t) {
      blk = block_of(m)
      if (blk == "") blk = parent
      else if (blk != parent) {
        entered[blk, base(m)] += times
        if (entered[blk, base(m)] > inst[blk]) inst[blk] = entered[blk, base(m)]
      }
      for (i = 1; i <= ntypes[m]; i++) {
        t = types[m, i]
        if (t in modules) walk(t, times * cnt[m, t], blk)
        else add(blk, t, times * cnt[m, t])
      }
    }
    /^=== design hierarchy ===/ { mod = ""; hier = 1; next }
    /^=== / { mod = $2; modules[mod] = 1; next }
    hier && NF == 2 && $1 !~ /^\$/ && $1 !~ /^ts_/ && $2 ~ /^[0-9]+$/ { add("total", $1, $2); next }
    mod != "" && NF == 2 && $2 ~ /^[0-9]+$/ { ntypes[mod]++; types[mod, ntypes[mod]] = $1; cnt[mod, $1] = $2 }
    END {
      walk(top, 1, "")
      inst["total"] = 1
      n = split("receiver scene_memory scanout worker sphere_test sqrt_unit shade reflect unit sphere_unit " \
                "shade_reflect camera world prepare cull tiles device rom_host board total", order, " ")
      for (i = 1; i <= n; i++) {
        b = order[i]
        if (!(b in inst)) continue
        k = inst[b]
        printf "%s\t%s\t%d\t%d\t%d\t%d\t%d\t%d\t%d\n", preset, b, k, dsp[b] / k, lut[b] / k, ram[b] / k, ff[b] / k,
               bram[b] / k, carry[b] / k
      }
    }' "$2"
}

# chip PRESET N STAT [STAT1]: the chip table of a run with N workers or units (and, given the run with one, the
# largest N).
chip() {
  local preset=$1 n=$2 lut ram ff dsp bram lut1 ram1 ff1 dsp1 bram1
  read -r lut ram ff dsp bram <<<"$(count "$3")"
  if [ -n "${4:-}" ]; then read -r lut1 ram1 ff1 dsp1 bram1 <<<"$(count "$4")"; else lut1=$lut ram1=$ram ff1=$ff dsp1=$dsp bram1=$bram; fi
  awk -v n="$n" -v preset="$preset" -v one="${4:+1}" \
      -v top="$(preset_top "$preset")" -v noun="$(preset_noun "$preset")" \
      -v lut="$lut" -v ram="$ram" -v ff="$ff" -v dsp="$dsp" -v bram="$bram" \
      -v lut1="$lut1" -v ram1="$ram1" -v ff1="$ff1" -v dsp1="$dsp1" -v bram1="$bram1" 'BEGIN {
    printf "%s, %s, %d %ss, on the XC7A100T:\n", top, preset, n, noun
    printf "  %-24s %10s %10s %6s\n", "", "used", "of", "share"
    row("LUTs (logic + memory)", lut + ram, 63400)
    row("  of them as memory", ram, 63400)
    row("flip-flops", ff, 126800)
    row("DSP48E1", dsp, 240)
    row("block RAM (36 Kbit)", bram, 135)
    if (one == "") exit
    best = 640; limit = ""
    fit("LUTs", lut + ram, lut1 + ram1, 63400)
    fit("flip-flops", ff, ff1, 126800)
    fit("DSP48E1", dsp, dsp1, 240)
    fit("block RAM", bram, bram1, 135)
    if (best < 1) printf "  not even one %s fits (%s)\n", noun, limit
    else printf "  largest N that fits: %d (each %s adds its share of the N-th; the limit is %s)\n", best, noun, limit
  }
  function row(name, used, of) { printf "  %-24s %10.1f %10d %5.1f%%\n", name, used, of, 100 * used / of }
  function fit(name, at_n, at_1, cap,    per, most) {
    per = (at_n - at_1) / (n - 1)
    if (per <= 0) return
    most = 1 + int((cap - at_1) / per)
    if (most < best) { best = most; limit = name }
  }'
}

# rtl_version: the commit of the tree's rtl/, and whether it has changes since.
rtl_version() {
  local commit
  commit=$(git rev-parse --short=12 HEAD 2>/dev/null) || { echo "not in a git work tree"; return; }
  if [ -n "$(git status --porcelain -- rtl 2>/dev/null | grep -v synth_table.tsv)" ]; then echo "$commit with changes to rtl/"; else echo "$commit"; fi
}

print_blocks() {
  awk -F '\t' 'BEGIN { printf "  %-13s %9s %8s %8s %8s %8s %7s %7s\n", "block", "instances", "DSP48E1", "LUTs",
                       "LUT RAM", "FFs", "RAMB18", "CARRY4" }
               { printf "  %-13s %9d %8d %8d %8d %8d %7d %7d\n", $2, $3, $4, $5, $6, $7, $8, $9 }'
}

command -v yosys >/dev/null || { echo "$0: yosys not found (Debian: apt-get install yosys)" >&2; exit 1; }
mkdir -p "$out"
start_time=$SECONDS

case "${1:-}" in
  "") usage ;;
  table)
    shift
    presets=("$@")
    ((${#presets[@]})) || presets=(wide board-2023 artix)
    for p in "${presets[@]}"; do preset_params "$p" >/dev/null || usage; done
    echo "synthesising every block of ${presets[*]} (yosys synth_xilinx -family xc7; logs in $out/) ..." >&2
    declare -A prows pparams prtl
    for p in "${presets[@]}"; do
      n=$(preset_workers "$p")
      synth "$p" "$n"
      prows[$p]=$(blocks "$p" "$out/$p-n$n.stat")$'\n'
      pparams[$p]="# params $p $(echo N="$n" $(preset_params "$p"))"
      prtl[$p]="# RTL of $p: $(rtl_version)"
    done
    # The presets not synthesised this time keep their rows, parameters and RTL version (a table written before
    # versions were kept per preset has one "# RTL:" line for all).
    all=(wide board-2023 artix)
    for q in "${all[@]}"; do
      [ -n "${prows[$q]:-}" ] || [ ! -f "$table_file" ] || {
        kept=$(awk -F'\t' -v q="$q" '$1 == q' "$table_file")
        [ -z "$kept" ] && continue
        prows[$q]=$kept$'\n'
        pparams[$q]=$(grep "^# params $q " "$table_file" || true)
        prtl[$q]=$(grep "^# RTL of $q: " "$table_file" || sed -n "s/^# RTL: /# RTL of $q: /p" "$table_file")
      }
    done
    rows=""
    for q in "${all[@]}"; do rows+=${prows[$q]:-}; done
    {
      echo "# What Yosys's synth_xilinx -family xc7 builds of each block of a preset's top (rtl/: ts_device, and"
      echo "# ts_artix_device for artix), per instance, as the preset configures it."
      echo "# Regenerate with: scripts/synth.sh table   ($(yosys -V))"
      for q in "${all[@]}"; do [ -z "${prtl[$q]:-}" ] || echo "${prtl[$q]}"; done
      echo "# Blocks: scripts/synth.sh's header; the ledger (src/tripsitter/device/resources.h, rtl_blocks) is held to"
      echo "# this table within 10% (DSP48E1, LUTs + LUT RAM, RAMB18) by src/tripsitter/device/resources_test.cpp."
      echo "# LUTs: LUT1..LUT6 (INV not counted); lutram: LUTs as memory (LUT RAM, shift registers); ramb18: a RAMB36 is 2."
      for q in "${all[@]}"; do [ -z "${pparams[$q]:-}" ] || echo "${pparams[$q]}"; done
      printf "# preset\tblock\tinstances\tdsp48e1\tluts\tlutram\tffs\tramb18\tcarry4\n"
      printf "%s" "$rows"
    } >"$table_file"
    for p in "${presets[@]}"; do printf "%s" "${prows[$p]}"; done | print_blocks
    echo "written: $table_file ($((SECONDS - start_time)) s)" >&2
    ;;
  arty)
    mode=${2:-standalone}
    [ "$mode" = standalone ] || [ "$mode" = spi ] || usage
    echo "synthesising ts_arty_top ($mode: the artix device, 9 sphere units, on the Arty A7-100T;" \
         "yosys synth_xilinx -family xc7; logs in $out/) ..." >&2
    synth_board "$mode"
    chip "arty-$mode" 9 "$out/arty-$mode.stat"
    echo "blocks (per instance; scripts/synth.sh's header says which modules each holds):"
    blocks "arty-$mode" "$out/arty-$mode.stat" | print_blocks
    echo "($((SECONDS - start_time)) s)" >&2
    ;;
  wide|board-2023|artix)
    preset=$1
    n=$(preset_workers "$preset")
    top=$(preset_top "$preset")
    echo "synthesising $top as $preset configures it ($n $(preset_noun "$preset")s;" \
         "yosys synth_xilinx -family xc7; logs in $out/) ..." >&2
    synth "$preset" "$n" flat
    chip "$preset" "$n" "$out/$preset-n$n.stat"
    echo "blocks (per instance; scripts/synth.sh's header says which modules each holds):"
    blocks "$preset" "$out/$preset-n$n.stat" | print_blocks
    echo "logic depth (scripts/logic_depth.sh $out/$preset-n$n.json):"
    scripts/logic_depth.sh "$out/$preset-n$n.json" "$top" 5 | sed 's/^/  /'
    echo "($((SECONDS - start_time)) s)" >&2
    ;;
  *)
    n=$1
    preset=${2:-board-2023}
    if ! [[ "$n" =~ ^[1-9][0-9]*$ ]] || ((n > 640)); then usage; fi
    preset_params "$preset" >/dev/null || { echo "$0: unknown preset '$preset' (wide, board-2023 or artix)" >&2; exit 2; }
    echo "synthesising $(preset_top "$preset") ($preset) with $n $(preset_noun "$preset")s and with 1" \
         "(yosys synth_xilinx -family xc7; logs in $out/) ..." >&2
    synth "$preset" "$n"
    if ((n > 1)); then
      synth "$preset" 1
      chip "$preset" "$n" "$out/$preset-n$n.stat" "$out/$preset-n1.stat"
    else
      chip "$preset" "$n" "$out/$preset-n$n.stat"
      echo "  (give N > 1 for the largest N that fits)"
    fi
    ;;
esac
