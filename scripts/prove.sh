#!/usr/bin/env bash
# The RTL's formal proofs (docs/rtl.md, "Proofs"): every property written in an `ifdef FORMAL` block of an rtl/ module,
# checked with Debian's yosys, yosys-smtbmc and z3.
#
#   scripts/prove.sh [--deep] [PROOF...]     each proof (default: all): bounded model checking from reset to the
#                                            proof's depth, then, where the proof says it closes, k-induction at that
#                                            depth; prints one line per property: proven (k-induction), bounded
#                                            (no violation within depth k of reset) or FAILED with the counterexample
#                                            as a VCD. --deep: the proofs' deep depths (minutes, for people)
#   scripts/prove.sh --planted [PROOF...]    each proof's planted violations: a copy of the RTL with one change
#                                            (a sed expression) that the named property must catch; prints caught
#                                            (with the trace) or MISSED
#   scripts/prove.sh --list                  the proofs and planted violations, one a line, tab-separated:
#                                            proof NAME TOP DEPTH MODE PARAMS, plant NAME PROPERTY FILE (how
#                                            proofs_test and scripts/lint_rtl.sh read the manifests)
#
# The proofs live beside their blocks, in rtl/<block>/proofs.tsv, tab-separated, one row each:
#   proof  NAME  TOP  DEPTH  DEEP_DEPTH  MODE  SOURCES  PARAMS
#     MODE: induction (the proof must close by k-induction at DEPTH) or bmc (bounded only: the row's comment says
#     why); SOURCES: space-separated paths from the repository's root, packages first; PARAMS: NAME=VALUE ... or -
#   plant  NAME  PROPERTY  FILE  SED
#     the proof NAME, run on a copy of its sources with the sed expression SED applied to FILE, must report
#     PROPERTY as failed (within DEPTH or at the induction step); the expression must change the file.
# Lines starting with # are comments.
#
# Work goes to build/formal/<proof>/ (FORMAL_BUILD_DIR=DIR elsewhere): the model (model.smt2), the logs and the
# counterexamples (bmc.vcd: a trace from reset; induction.vcd: a state from which k steps hold and the next fails).
# Exit 0: every property proven or bounded as its proof's MODE says (--planted: every plant caught); 1: a property
# failed or a plant was missed; 2: bad usage or a missing tool.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  echo "usage: $0 [--deep] [PROOF...]  |  $0 --planted [PROOF...]  |  $0 --list" >&2
  exit 2
}
action=prove deep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --deep) deep=1 ;;
    --planted) action=planted ;;
    --list) action=list ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) usage ;;
    *) break ;;
  esac
  shift
done
wanted=("$@")

# --list reads the manifests alone; the proofs need the tools.
if [ "$action" != list ]; then
  for tool in yosys yosys-smtbmc z3; do
    if ! command -v "$tool" >/dev/null; then
      echo "$tool is missing: apt-get install yosys z3" >&2
      exit 2
    fi
  done
fi

root=${FORMAL_BUILD_DIR:-build/formal}
mkdir -p "$root"

# The manifests' rows, without comments and blank lines, each prefixed by its file and line for messages.
rows() {
  local f n line
  for f in rtl/*/proofs.tsv; do
    n=0
    while IFS= read -r line || [ -n "$line" ]; do
      n=$((n + 1))
      case "$line" in ''|'#'*) continue ;; esac
      printf '%s:%d\t%s\n' "$f" "$n" "$line"
    done < "$f"
  done
}

declare -A top depth deep_depth mode sources params where
proofs=()
plants=()
while IFS=$'\t' read -r at kind a b c d e f g; do
  case "$kind" in
    proof)
      [ -n "$g" ] || { echo "$at: a proof row has 8 fields: proof NAME TOP DEPTH DEEP_DEPTH MODE SOURCES PARAMS" >&2; exit 2; }
      [ -z "${top[$a]:-}" ] || { echo "$at: proof $a is already defined at ${where[$a]}" >&2; exit 2; }
      case "$e" in induction|bmc) ;; *) echo "$at: MODE is induction or bmc, not '$e'" >&2; exit 2 ;; esac
      top[$a]=$b depth[$a]=$c deep_depth[$a]=$d mode[$a]=$e sources[$a]=$f params[$a]=$g where[$a]=$at
      proofs+=("$a")
      ;;
    plant)
      [ -n "$d" ] || { echo "$at: a plant row has 5 fields: plant NAME PROPERTY FILE SED" >&2; exit 2; }
      plants+=("$at"$'\t'"$a"$'\t'"$b"$'\t'"$c"$'\t'"$d")
      ;;
    *) echo "$at: unknown row kind '$kind' (proof or plant)" >&2; exit 2 ;;
  esac
done < <(rows)
for p in "${plants[@]}"; do
  IFS=$'\t' read -r at name _ <<< "$p"
  [ -n "${top[$name]:-}" ] || { echo "$at: plant of unknown proof $name" >&2; exit 2; }
done
for w in "${wanted[@]}"; do
  [ -n "${top[$w]:-}" ] || { echo "no such proof: $w (scripts/prove.sh --list)" >&2; exit 2; }
done
selected() {
  local w
  ((${#wanted[@]})) || return 0
  for w in "${wanted[@]}"; do [ "$w" = "$1" ] && return 0; done
  return 1
}

if [ "$action" = list ]; then
  for p in "${proofs[@]}"; do
    selected "$p" && printf 'proof\t%s\t%s\t%s\t%s\t%s\n' "$p" "${top[$p]}" "${depth[$p]}" "${mode[$p]}" "${params[$p]}"
  done
  for p in "${plants[@]}"; do
    IFS=$'\t' read -r _ name prop file _ <<< "$p"
    selected "$name" && printf 'plant\t%s\t%s\t%s\n' "$name" "$prop" "$file"
  done
  exit 0
fi

# model DIR PROOF [FILE SED]: the proof's model as SMT-LIB 2 in DIR/model.smt2, with the sed expression applied to a
# copy of FILE when given. Prints the properties' names, one a line, to DIR/properties.
model() {
  local dir=$1 name=$2 file=${3:-} expr=${4:-} list=() s read_cmd chparam=""
  mkdir -p "$dir"
  for s in ${sources[$name]}; do
    [ -f "$s" ] || { echo "${where[$name]}: no such source: $s" >&2; return 2; }
    if [ -n "$file" ] && [ "$s" = "$file" ]; then
      sed -e "$expr" "$s" > "$dir/planted.sv"
      if cmp -s "$s" "$dir/planted.sv"; then
        echo "the planted change leaves $file as it is: $expr" >&2
        return 2
      fi
      s=$dir/planted.sv
    fi
    list+=("$s")
  done
  if [ "${params[$name]}" != - ]; then
    for s in ${params[$name]}; do chparam+="chparam -set ${s%%=*} ${s#*=} ${top[$name]}; "; done
  fi
  read_cmd="read_verilog -formal -sv ${list[*]}; $chparam prep -top ${top[$name]}; async2sync; dffunmap; write_smt2 -wires $dir/model.smt2"
  if ! yosys -q -l "$dir/yosys.log" -p "$read_cmd" > /dev/null 2>&1; then
    echo "$name: yosys could not read the model (log: $dir/yosys.log)" >&2
    grep -E "ERROR|rror:" "$dir/yosys.log" | head -n 5 | sed 's/^/  /' >&2
    return 2
  fi
  grep -oP '^; yosys-smt2-assert \d+ \K\S+' "$dir/model.smt2" | sort -u > "$dir/properties"
  # Every property has a name (a label: `p_what: assert (...)`), which is how this script and docs/rtl.md name it.
  if grep -q '^\$' "$dir/properties"; then
    echo "$name: an assertion without a label (give each one a name, p_<what>:):" >&2
    grep '^\$' "$dir/properties" | sed 's/^/  /' >&2
    return 2
  fi
}

# failed_in LOG: the properties yosys-smtbmc reports as failed in its log, space-separated (several can fail in the
# same step).
failed_in() {
  grep -oP 'Assert(ion)? failed in \S+ \K\S+' "$1" | sed 's/^(//; s/)$//' | sort -u | tr '\n' ' ' | sed 's/ $//'
}

# check DIR K MODE: bounded model checking to depth K (and k-induction at K when MODE is induction) on DIR/model.smt2.
# Sets `verdict` to proven, bounded or failed, `failed_property` to the assertions that failed, `trace` to the VCD.
check() {
  local dir=$1 k=$2 m=$3
  verdict=bounded failed_property="" trace=""
  if ! yosys-smtbmc -s z3 --unroll --presat -t "$k" --dump-vcd "$dir/bmc.vcd" "$dir/model.smt2" > "$dir/bmc.log" 2>&1; then
    verdict=failed trace=$dir/bmc.vcd
    failed_property=$(failed_in "$dir/bmc.log")
    return
  fi
  [ "$m" = induction ] || return 0
  if yosys-smtbmc -s z3 --unroll --presat -i -t "$k" --dump-vcd "$dir/induction.vcd" "$dir/model.smt2" > "$dir/induction.log" 2>&1; then
    verdict=proven
  else
    verdict=failed trace=$dir/induction.vcd
    failed_property=$(failed_in "$dir/induction.log")
  fi
}

status=0
start=$SECONDS
if [ "$action" = prove ]; then
  for p in "${proofs[@]}"; do
    selected "$p" || continue
    dir=$root/$p k=${depth[$p]}
    ((deep)) && k=${deep_depth[$p]}
    t0=$SECONDS
    model "$dir" "$p" || exit 2
    check "$dir" "$k" "${mode[$p]}"
    seconds=$((SECONDS - t0))
    while read -r prop; do
      case "$verdict" in
        proven) printf '%-22s %-34s proven (k-induction, k = %d)\n' "$p" "$prop" "$k" ;;
        bounded) printf '%-22s %-34s bounded to depth %d\n' "$p" "$prop" "$k" ;;
        failed)
          if [[ " $failed_property " == *" $prop "* ]]; then
            if [ "$trace" = "$dir/bmc.vcd" ]; then
              printf '%-22s %-34s FAILED within depth %d: %s\n' "$p" "$prop" "$k" "$trace"
            else
              printf '%-22s %-34s FAILED the induction step at k = %d: %s\n' "$p" "$prop" "$k" "$trace"
            fi
          else
            printf '%-22s %-34s not decided (the proof stopped at %s)\n' "$p" "$prop" "${failed_property:-an error}"
          fi
          ;;
      esac
    done < "$dir/properties"
    if [ "$verdict" = failed ]; then
      status=1
      [ -n "$failed_property" ] || echo "$p: yosys-smtbmc failed without naming a property (logs in $dir)" >&2
    fi
    echo "$p: ${mode[$p]} at depth $k, $(wc -l < "$dir/properties") properties, ${seconds} s" >&2
  done
else
  for row in "${plants[@]}"; do
    IFS=$'\t' read -r at name prop file expr <<< "$row"
    selected "$name" || continue
    n=$(printf '%s' "$at" | tr -c 'a-zA-Z0-9' _)
    dir=$root/planted/$name-$n
    model "$dir" "$name" "$file" "$expr" || exit 2
    if ! grep -qx -- "$prop" "$dir/properties"; then
      echo "$at: the proof $name has no property $prop" >&2
      exit 2
    fi
    check "$dir" "${depth[$name]}" "${mode[$name]}"
    if [ "$verdict" = failed ] && [[ " $failed_property " == *" $prop "* ]]; then
      printf '%-22s %-34s caught: %s\n' "$name" "$prop" "$trace"
    else
      printf '%-22s %-34s MISSED (%s%s): %s in %s\n' "$name" "$prop" "$verdict" \
        "${failed_property:+, $failed_property failed instead}" "$expr" "$file"
      status=1
    fi
  done
fi
echo "$action: $((SECONDS - start)) s" >&2
exit $status
