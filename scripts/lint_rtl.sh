#!/usr/bin/env bash
# Lints every module of rtl/ as a top, with its default parameters, the way the tests and synthesis read it
# (docs/rtl.md, "Lint"):
#   - Verilator 5.006 --lint-only -Wall, as synthesis reads the module, and each proof's top with its formal
#     properties (+define+FORMAL) and the proof's parameters (scripts/prove.sh --list);
#   - Yosys 0.23 read_verilog -sv of every source, then hierarchy -check of each module as the top; and the same with
#     read_verilog -sv -formal for each module whose hierarchy has a source that -formal reads differently (one that
#     names FORMAL or SYNTHESIS, the macros -formal swaps, or a keyword, system function or attribute of assertions
#     and properties), from that hierarchy's sources. In the other modules' hierarchies every source reads the same
#     under -formal, so their check would repeat the first one's word for word (ts_path_display's tables, built at
#     elaboration, were most of it: the whole lint took 71.8 and 74.5 s reading every source twice, 60.8 and 69.8 s
#     now, runs alternated on 2 cores shared with other work, `time scripts/lint_rtl.sh`);
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

# The -formal pass's modules: those whose hierarchy reaches a source that -formal reads differently. A module's
# hierarchy here is every module its code names (comments left out), and theirs, and so on: a name that is not an
# instance only adds a module to check.
declare -A file_of names differs formal_read
formal_words='assert|assume|cover|restrict|property|sequence|rand|const|checker|endchecker|eventually|s_eventually'
formal_words+='|anyconst|anyseq|allconst|allseq|past|stable|rose|fell|changed|initstate|global_clock'
for f in "${others[@]}"; do
  file_of[$(basename "$f" .sv)]=$f
done
for f in "${others[@]}"; do
  m=$(basename "$f" .sv)
  code=$(sed 's://.*$::' "$f" | perl -0pe 's:/\*.*?\*/::gs')
  names[$m]=$(grep -oP '\bts_\w+\b' <<< "$code" | sort -u | tr '\n' ' ')
  if grep -qP "FORMAL|SYNTHESIS|\\b($formal_words)\\b" <<< "$code"; then
    differs[$m]=1
  fi
done
formal_modules=()
for m in "${modules[@]}"; do
  declare -A seen=()
  todo=("$m") reaches=0
  while ((${#todo[@]})); do
    x=${todo[0]}
    todo=("${todo[@]:1}")
    [ -z "${seen[$x]:-}" ] && [ -n "${file_of[$x]:-}" ] || continue
    seen[$x]=1
    [ -n "${differs[$x]:-}" ] && reaches=1
    for y in ${names[$x]}; do todo+=("$y"); done
  done
  if ((reaches)); then
    formal_modules+=("$m")
    for x in "${!seen[@]}"; do formal_read[$x]=1; done
  fi
  unset seen
done
formal_sources=("${packages[@]}")
for f in "${others[@]}"; do
  [ -n "${formal_read[$(basename "$f" .sv)]:-}" ] && formal_sources+=("$f")
done

# Yosys works in the board's folder, where the ROM host's $readmemh finds its image by name (as scripts/synth.sh does).
# The Xilinx primitives an RTL block instantiates (the clock gate's BUFGCE) are read as black boxes from Yosys's own
# library, as synth_xilinx reads them.
for formal in "" "-formal"; do
  if [ -z "$formal" ]; then
    tops=("${modules[@]}") files=("${sources[@]}")
  else
    tops=("${formal_modules[@]}") files=("${formal_sources[@]}")
    ((${#tops[@]})) || continue
  fi
  script=""
  for m in "${tops[@]}"; do
    script+="design -load read; hierarchy -check -top $m; "
  done
  absolute=("${files[@]/#/$PWD/}")
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
