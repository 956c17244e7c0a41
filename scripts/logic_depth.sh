#!/usr/bin/env bash
# The longest register-to-register paths of a LUT-mapped netlist, in LUT levels: a walk over Yosys's write_json
# of a flattened design after synth_xilinx (scripts/synth.sh writes one for each whole top it synthesises).
#
#   scripts/logic_depth.sh NETLIST.json [TOP] [PATHS]     (TOP: the top module, ts_device by default, ts_artix_device
#                                                          for artix; PATHS: 5)
#
# Prints the deepest path and the PATHS deepest (one per destination register, so that a bus is not listed bit by
# bit), each with its LUT levels, the CARRY4 cells and MUXF7/MUXF8 cells it passes, its start and its end.
#
# The counting (Yosys's `ltp -noff` counts every cell, carries and flip-flops of this family included, so it
# cannot be used as it is):
#   - a LUT1..LUT6 is one level, and so is the read of a LUT RAM (RAM32M, RAM64M, RAM*X1D, RAM*X1S), from its
#     read address to its output;
#   - CARRY4 adds no level (a carry chain is counted apart: CARRY4 cells on the path), nor does MUXF7/MUXF8 (the
#     slice's wide-function multiplexers, counted apart) nor INV (Vivado folds an inverter into its neighbour);
#     carry bit i of a CARRY4 depends on its inputs 0..i only;
#   - paths start at flip-flops, at the outputs of block RAM, shift registers (SRL*), LUT RAM contents, of a
#     DSP48E1 with any internal register, and at the top's inputs; they end at the inputs of the same cells and
#     at the top's outputs. A DSP48E1 without registers is passed through, counted apart, with no level.
# Needs only awk (POSIX; Debian's mawk will do).
set -euo pipefail

json=${1:-}
top=${2:-ts_device}
paths=${3:-5}
if [ -z "$json" ] || [ ! -r "$json" ]; then
  echo "usage: $0 NETLIST.json [TOP] [PATHS]   (write_json of a flattened, LUT-mapped design)" >&2
  exit 2
fi

awk -v top="$top" -v npaths="$paths" -v trace="${LOGIC_DEPTH_TRACE:-0}" '
function strip(s) { gsub(/^ *"|",?$|": .*$/, "", s); return s }
# What a cell is: "seq" (its outputs start paths, its inputs end them), "lut" (one level), "ram" (LUT RAM: read
# address to output is one level, the rest ends), "carry", "muxf", "inv", "dsp" (no register) or "wire".
function kind(t, c) {
  if (t ~ /^LUT[1-6]$/) return "lut"
  if (t ~ /^(FD[RSCP]E|FD[RSCP]E_1|LD[CP]E|SRL16E|SRLC16E|SRLC32E|RAMB18E1|RAMB36E1)$/) return "seq"
  if (t ~ /^RAM(32M|64M|32X1D|64X1D|128X1D|32X1S|64X1S|128X1S|256X1S)$/) return "ram"
  if (t == "CARRY4") return "carry"
  if (t == "MUXF7" || t == "MUXF8") return "muxf"
  if (t == "INV") return "inv"
  if (t == "DSP48E1") return dspreg[c] ? "seq" : "dsp"
  return "wire"
}
# Whether output (op, oi) of cell c depends on input (ip, ii).
function feeds(c, op, oi, ip, ii,    k) {
  k = ck[c]
  if (k == "carry") return ip == "CI" || ip == "CYINIT" || ii <= oi
  if (k == "ram") {
    if (ct[c] == "RAM64M" || ct[c] == "RAM32M") return ip == "ADDR" substr(op, 3, 1)
    if (op == "DPO") return ip ~ /^DPRA/
    return ip ~ /^A[0-9]*$/ || ip == "ADDR"
  }
  return 1
}
# The arrival of bit b: lv (LUT levels), cy (CARRY4s), mx (MUXF7/8), dp (unregistered DSPs), pv (the bit it came
# from, "" at a start). Memoised; a combinational loop (none in a synchronous design) is cut where it closes.
function arrive(b,    c, k, n, i, parts, e, best, blv, bcy, bmx, bdp, x, w) {
  if (b in lv) return
  c = drv[b]
  k = (c == "") ? "" : ck[c]
  lv[b] = 0; cy[b] = 0; mx[b] = 0; dp[b] = 0; pv[b] = ""
  if (c == "" || k == "seq") return
  n = split(cin[c], parts, ";")
  best = ""; blv = -1
  for (i = 1; i <= n; i++) {
    if (parts[i] == "") continue
    split(parts[i], e, " ")
    if (!feeds(c, dport[b], didx[b], e[1], e[2] + 0)) continue
    x = e[3]
    if (x !~ /^[0-9]+$/) continue
    arrive(x)
    if (lv[x] > blv || (lv[x] == blv && cy[x] > bcy)) { best = x; blv = lv[x]; bcy = cy[x]; bmx = mx[x]; bdp = dp[x] }
  }
  w = (k == "lut" || k == "ram") ? 1 : 0
  if (best == "") { lv[b] = w; return }
  lv[b] = blv + w; cy[b] = bcy + (k == "carry"); mx[b] = bmx + (k == "muxf"); dp[b] = bdp + (k == "dsp"); pv[b] = best
}
function bitname(b) { return (b in nm) ? nm[b] : ("bit " b) }
function cellname(c) { return ((c in cq) && (cq[c] in nm)) ? nm[cq[c]] : c }
function deeper(x, y) { return lv[x] > lv[y] || (lv[x] == lv[y] && cy[x] > cy[y]) }
BEGIN { depth = 0 }
# Structure of write_json: modules at 4 spaces, their sections at 6, cells and nets at 8, fields at 10, 12.
/^    "/ { mod = strip($0); inmod = (mod == top); section = ""; next }
!inmod { next }
/^      "(ports|cells|netnames)": \{/ { section = strip($0); next }
section == "ports" && /^        "/ { pname = strip($0); next }
section == "ports" && /"direction":/ { pdir = $2; gsub(/[",]/, "", pdir); next }
section == "ports" && /"bits":/ {
  line = $0; sub(/.*\[ */, "", line); sub(/ *\].*/, "", line); nb = split(line, bits, /, */)
  for (i = 1; i <= nb; i++) {
    b = bits[i]; if (b !~ /^[0-9]+$/) continue  # "0", "1", "x": constants
    if (b !~ /^[0-9]+$/) continue
    if (pdir == "output") { nend++; endbit[nend] = b; endcell[nend] = "output " pname (nb > 1 ? "[" (i - 1) "]" : "") }
  }
  next
}
section == "cells" && /^        "/ { cell = strip($0); ncell++; sub_ = ""; next }
section == "cells" && /^          "type":/ { t = $2; gsub(/[",]/, "", t); ct[cell] = t; next }
section == "cells" && /^          "(parameters|port_directions|connections|attributes)":/ { sub_ = strip($0); next }
section == "cells" && sub_ == "parameters" && /"(AREG|BREG|MREG|PREG|ADREG|DREG|CREG)":/ {
  v = $2; gsub(/[",]/, "", v); if (v ~ /1/) dspreg[cell] = 1; next
}
section == "cells" && sub_ == "port_directions" && /^            "/ {
  p = strip($0); d = $2; gsub(/[",]/, "", d); pd[cell, p] = d; next
}
section == "cells" && sub_ == "connections" && /^            "/ {
  p = strip($0)
  line = $0; sub(/.*\[ */, "", line); sub(/ *\].*/, "", line); nb = split(line, bits, /, */)
  if (!(cell in ck)) ck[cell] = kind(ct[cell], cell)
  for (i = 1; i <= nb; i++) {
    b = bits[i]; if (b !~ /^[0-9]+$/) continue  # "0", "1", "x": constants
    if (pd[cell, p] == "output") {
      if (b ~ /^[0-9]+$/) { drv[b] = cell; dport[b] = p; didx[b] = i - 1; if (p == "Q") cq[cell] = b }
    } else if (p != "C" && p != "CLK" && p != "WCLK" && p !~ /^CLK/) {
      cin[cell] = cin[cell] p " " (i - 1) " " b ";"
      k = ck[cell]
      if (b ~ /^[0-9]+$/ && (k == "seq" || k == "ram")) { nend++; endbit[nend] = b; endcell[nend] = cell; endport[nend] = p }
    }
  }
  next
}
section == "netnames" && /^        "/ { net = strip($0); hide = 1; next }
section == "netnames" && /"hide_name":/ { hide = ($2 ~ /1/); next }
section == "netnames" && /^          "bits":/ {
  if (hide || net ~ /\$/) next
  line = $0; sub(/.*\[ */, "", line); sub(/ *\].*/, "", line); nb = split(line, bits, /, */)
  for (i = 1; i <= nb; i++) {
    b = bits[i]; if (b !~ /^[0-9]+$/) continue  # "0", "1", "x": constants
    if (b ~ /^[0-9]+$/ && (!(b in nm) || length(net) < nmlen[b]))
      { nm[b] = net (nb > 1 ? "[" (i - 1) "]" : ""); nmlen[b] = length(net) }
  }
  next
}
END {
  if (!ncell) { printf "logic_depth: no cells in module %s\n", top > "/dev/stderr"; exit 1 }
  # Each destination (a register vector, bits and instances folded) keeps its deepest end.
  for (i = 1; i <= nend; i++) {
    b = endbit[i]
    arrive(b)
    e = endcell[i]
    dest = (e ~ /^output /) ? e : cellname(e)
    gsub(/\[[0-9]+\]/, "[]", dest); gsub(/\.[0-9]+/, ".*", dest)
    if (!(dest in pick) || deeper(b, endbit[pick[dest]])) pick[dest] = i
  }
  for (shown = 1; shown <= npaths; shown++) {
    best = 0
    for (dest in pick) {
      i = pick[dest]
      if (!(i in used) && (best == 0 || deeper(endbit[i], endbit[best]))) best = i
    }
    if (best == 0) break
    used[best] = 1
    b = endbit[best]
    e = endcell[best]
    s = b
    while (pv[s] != "") s = pv[s]
    sc = drv[s]
    start = (sc == "") ? ("input " bitname(s)) : (bitname(s) " (" ct[sc] ")")
    if (shown == 1) printf "longest path: %d LUT levels (%d CARRY4, %d MUXF7/8, %d DSP48E1 without registers)\n", lv[b], cy[b], mx[b], dp[b]
    printf "  %d. %2d levels, %2d CARRY4, %d MUXF: %s -> %s%s\n", shown, lv[b], cy[b], mx[b], start,
           (e ~ /^output /) ? e : cellname(e) " (" ct[e] (endport[best] != "" && ct[e] !~ /^FD/ ? " " endport[best] : "") ")",
           dp[b] ? sprintf(" [through %d DSP48E1]", dp[b]) : ""
    if (trace) {
      for (s = b; s != ""; s = pv[s]) printf "       %s <- %s\n", bitname(s), (drv[s] == "" ? "(input)" : ct[drv[s]] " " drv[s])
    }
  }
}' "$json"
