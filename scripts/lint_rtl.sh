#!/usr/bin/env bash
# Lints every module of rtl/ as a top, with its default parameters, the way the tests and synthesis read it
# (docs/rtl.md, "Lint"):
#   - Verilator 5.006 --lint-only -Wall, as synthesis reads the module, and each proof's top with its formal
#     properties (+define+FORMAL) and the proof's parameters (scripts/prove.sh --list);
#   - Yosys 0.23 read_verilog -sv (and -formal) of every source, then hierarchy -check of each module as the top;
#   - every Verilator waiver (lint_off) says why, in a comment on its line, the line before, or before its lint_on.
# Prints each warning as the tool does, then one summary line; exit 0 when nothing was found, 1 otherwise, 2 when a
# tool is missing.
#
#   scripts/lint_rtl.sh
set -euo pipefail
cd "$(dirname "$0")/.."

for tool in verilator yosys; do
  command -v "$tool" >/dev/null || { echo "$tool is missing: apt-get install verilator yosys" >&2; exit 2; }
done

# Packages first (blocks name ts_link_pkg::X, ts_artix_pkg::X and ts_path_pkg::X), then every other source.
packages=(rtl/receiver/ts_link_pkg.sv rtl/artix/ts_artix_pkg.sv rtl/path/ts_path_pkg.sv)
mapfile -t others < <(ls rtl/*/ts_*.sv rtl/boards/*/ts_*.sv | grep -v '_pkg\.sv$' | sort)
sources=("${packages[@]}" "${others[@]}")
mapfile -t modules < <(grep -ohP '^module\s+\K\w+' "${others[@]}" | sort)

log=$(mktemp)
trap 'rm -f "$log"' EXIT
found=0

# verilator_lint TOP ARGS...: Verilator -Wall on TOP with ARGS; prints what it says and counts a finding.
verilator_lint() {
  local top=$1
  shift
  # The board top reads its ROM image from its own folder.
  if ! verilator --lint-only -Wall -Irtl/boards/arty_a7 --top-module "$top" "$@" "${sources[@]}" > "$log" 2>&1 \
      || [ -s "$log" ]; then
    echo "verilator $top $*:"
    sed 's/^/  /' "$log"
    found=$((found + 1))
  fi
}
for m in "${modules[@]}"; do
  verilator_lint "$m"
done
# The formal properties as scripts/prove.sh reads them: each proof's top, with the proof's parameters. (A module's
# properties are read only when it is a proof's top; some name signals of one generate branch, e.g. ts_sqrt_unit's
# pipelined stages, which Verilator cannot resolve in an instance that elaborates the other.)
listing=$(scripts/prove.sh --list) || exit 2
while IFS=$'\t' read -r kind _ top _ _ params; do
  [ "$kind" = proof ] || continue
  args=(+define+FORMAL)
  if [ "$params" != - ]; then
    for p in $params; do args+=("-G$p"); done
  fi
  verilator_lint "$top" "${args[@]}"
done <<< "$listing"

script=""
for m in "${modules[@]}"; do
  script+="design -load read; hierarchy -check -top $m; "
done
# Yosys works in the board's folder, where the ROM host's $readmemh finds its image by name (as scripts/synth.sh does).
# The Xilinx primitives an RTL block instantiates (the clock gate's BUFGCE) are read as black boxes from Yosys's own
# library, as synth_xilinx reads them.
absolute=("${sources[@]/#/$PWD/}")
for formal in "" "-formal"; do
  (cd rtl/boards/arty_a7 && yosys -p "read_verilog -lib +/xilinx/cells_xtra.v; read_verilog -sv $formal ${absolute[*]};
       design -save read; $script") > "$log" 2>&1 || {
    echo "yosys read_verilog -sv $formal failed:"
    grep -E "ERROR" "$log" | sed 's/^/  /'
    found=$((found + 1))
  }
  if grep -q "Warning:" "$log"; then
    echo "yosys read_verilog -sv ${formal:+$formal }(then hierarchy -check of each module):"
    grep "Warning:" "$log" | sort -u | sed 's/^/  /'
    found=$((found + 1))
  fi
done

# A waiver is explained by a comment on its line, on the line before, or on a line before its lint_on.
unexplained=$(awk '
  FNR == 1 { open = 0 }
  /lint_off/ {
    open = 1; start = FNR; explained = ($0 ~ /\*\/[[:space:]]*\/\//) || (previous ~ /^[[:space:]]*\/\//)
  }
  open && FNR > start && /lint_on/ { if (!explained) print FILENAME ":" start; open = 0 }
  open && FNR > start && /\/\// { explained = 1 }
  { previous = $0 }' "${packages[@]}" "${others[@]}")
if [ -n "$unexplained" ]; then
  echo "waivers without a reason (a comment on the lint_off line, the line before, or before the lint_on):"
  printf '%s\n' "$unexplained" | sed 's/^/  /'
  found=$((found + 1))
fi

echo "lint: ${#modules[@]} modules, ${#sources[@]} files: $([ $found = 0 ] && echo clean || echo "$found findings")"
[ $found = 0 ]
