#!/usr/bin/env bash
# Builds the libFuzzer targets (the "fuzz" preset: clang, address and undefined-behaviour sanitizers),
# replays each target's saved regressions, then fuzzes it from its seed corpus. Prints each target's
# executions and coverage; exits 1 if any target crashed, failed an invariant, leaked or hung (the
# reproducer is then in <build>/artifacts/<target>/). See fuzz/README.md.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]   explore: SECONDS (default 20) per target, a random seed, and a
#                                           working corpus kept in <build>/corpus/<target> from run to run
#   scripts/fuzz.sh --ci RUNS [TARGET...]   CI: exactly RUNS executions per target (seed inputs included;
#                                           receiver_pins: at most 5,000, ci_most below),
#                                           seed 1, starting from the seeds alone, no corpus reloads: the
#                                           bound is work, not time, so a slow machine does the same runs
#   targets: wire_v1 wire_v2 wire_v3 receiver receiver_pins scene_json key_script (receiver_pins: only where
#            Verilator was found when the build was configured; with --ci at most 5,000 executions, fuzz/README.md)
#   FUZZ_BUILD_DIR=DIR builds in DIR instead of the preset's build/fuzz.
#   FUZZ_JOBS=N runs N targets at a time (default: the number of processors), the slowest started first; each
#   target's lines are printed in the order above once it is done. Every target is one process with its own seed,
#   bound and working corpus, so running it beside another changes none of its inputs.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  echo "usage: $0 [SECONDS] [TARGET...]  or  $0 --ci RUNS [TARGET...]" >&2
  exit 2
}
ci=0
if [ "${1:-}" = --ci ]; then
  ci=1
  shift
  [ $# -ge 1 ] || usage
fi
amount=${1:-20}
shift || true
case "$amount" in
  ''|*[!0-9]*) usage ;;
esac
targets=("$@")
all_targets=(wire_v1 wire_v2 wire_v3 receiver receiver_pins scene_json key_script)
explicit=${#targets[@]}
((explicit)) || targets=("${all_targets[@]}")
# Per target: the most executions a --ci run gives it (receiver_pins simulates the RTL clock by clock: 78 to 130
# executions a second on 2 shared cores, so 50,000 would take 6 to 11 minutes; fuzz/README.md), and options of its
# own (receiver_pins reads at most 560 bytes of an input: a longer one would be mutated where it is never read).
declare -A ci_most=([receiver_pins]=5000)
declare -A options=([receiver_pins]=-max_len=560)

if ! command -v clang++-14 >/dev/null; then
  echo "clang++-14 is missing: apt-get install clang-14 libclang-rt-14-dev" >&2
  exit 2
fi

root=${FUZZ_BUILD_DIR:-build/fuzz}
start=$SECONDS
cmake --preset fuzz -B "$root" >/dev/null
cmake --build "$root" --target fuzzers -j "$(nproc)" >/dev/null
echo "build: $((SECONDS - start)) s"

bin=$root/fuzz
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

# fuzz_target T: replays T's regressions, then fuzzes it; prints its lines; exit 1 if anything failed.
fuzz_target() {
  local t=$1 exe=$bin/${1}_fuzz artifacts=$root/artifacts/$1/ log=$root/logs/$1.log work runs bound failed=0
  if ((ci)); then
    # A fresh working corpus: what earlier runs found must not change what this one does.
    work=$root/corpus-ci/$t
    rm -rf "$work"
    runs=$amount
    [ -n "${ci_most[$t]:-}" ] && ((runs > ci_most[$t])) && runs=${ci_most[$t]}
    bound=(-runs="$runs" -seed=1 -reload=0)
  else
    work=$root/corpus/$t
    bound=(-max_total_time="$amount")
  fi
  mkdir -p "$work" "$artifacts"

  # Every saved reproducer must run clean (libFuzzer runs files given by name once each).
  local regressions
  mapfile -t regressions < <(find "fuzz/regressions/$t" -type f 2>/dev/null | sort)
  if ((${#regressions[@]})); then
    if ! "$exe" "${regressions[@]}" > "$root/logs/$t.regressions.log" 2>&1; then
      echo "$t: a regression input fails again (log: $root/logs/$t.regressions.log)"
      grep -E "invariant failed|ERROR:|SUMMARY:|Running:" "$root/logs/$t.regressions.log" | tail -n 6 | sed 's/^/  /'
      failed=1
    fi
  fi

  # The seeds are read and replayed first (libFuzzer writes new inputs to the first directory only).
  local dict=()
  [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="fuzz/dict/$t.dict")
  [ -n "${options[$t]:-}" ] && dict+=(${options[$t]})
  local status=0 t0=$SECONDS done_line rate
  "$exe" "$work" "fuzz/corpus/$t" "${dict[@]}" "${bound[@]}" -timeout=25 -print_final_stats=1 \
    -artifact_prefix="$artifacts" > "$log" 2>&1 || status=$?
  done_line=$(grep -E "^#[0-9]+[[:space:]]+DONE" "$log" | tail -n 1 || true)
  rate=$(grep -E "^stat::average_exec_per_sec" "$log" | awk '{print $2}' || true)
  if [ "$status" -eq 0 ]; then
    echo "$t: ${done_line:-no DONE line} ($((SECONDS - t0)) s, average exec/s: ${rate:-?};" \
      "regression inputs: ${#regressions[@]})"
  else
    echo "$t: CRASHED (exit $status; log: $log)"
    grep -E "invariant failed|ERROR:|SUMMARY:|Test unit written|^ +#[0-9]+ 0x" "$log" | head -n 14 | sed 's/^/  /'
    ((ci)) && echo "  the same run again: rm -rf $work; mkdir $work; $exe $work fuzz/corpus/$t ${dict[*]} ${bound[*]}"
    failed=1
  fi
  return $failed
}

runnable=()
for t in "${targets[@]}"; do
  exe=$bin/${t}_fuzz
  if [ ! -x "$exe" ] && [ "$t" = receiver_pins ] && ! ((explicit)); then
    echo "$t: not built (Verilator was not found when $root was configured): skipped"
    continue
  fi
  [ -x "$exe" ] || { echo "$t: no such target ($exe)" >&2; exit 2; }
  runnable+=("$t")
done
mkdir -p "$root/logs"

# The slowest first (fuzz/README.md has each target's time), so that the last to start are short ones.
slowest_first=(receiver receiver_pins wire_v2 wire_v3 scene_json key_script wire_v1)
order=()
for t in "${slowest_first[@]}" "${runnable[@]}"; do
  [[ " ${runnable[*]} " == *" $t "* && " ${order[*]} " != *" $t "* ]] && order+=("$t")
done
jobs=${FUZZ_JOBS:-$(nproc)}
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "FUZZ_JOBS must be a positive number" >&2; exit 2; }
declare -A pid
running=0
for t in "${order[@]}"; do
  if ((running >= jobs)); then
    wait -n || true
    running=$((running - 1))
  fi
  fuzz_target "$t" > "$root/logs/$t.report" 2>&1 &
  pid[$t]=$!
  running=$((running + 1))
done
failed=()
for t in "${runnable[@]}"; do
  wait "${pid[$t]}" || failed+=("$t")
  cat "$root/logs/$t.report"
done

echo "total: $((SECONDS - start)) s"
if ((${#failed[@]})); then
  echo "failed: ${failed[*]}"
  exit 1
fi
