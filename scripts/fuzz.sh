#!/usr/bin/env bash
# Builds the libFuzzer targets (the "fuzz" preset: clang, address and undefined-behaviour sanitizers) and
# runs each one for N seconds (default 20) from its seed corpus, after replaying its saved regressions.
# Prints each target's executions and coverage; exits 1 if any target crashed, failed an invariant, leaked
# or hung (the reproducer is then in build/fuzz/artifacts/<target>/). See fuzz/README.md.
#   scripts/fuzz.sh [SECONDS] [TARGET...]      targets: wire_v1 wire_v2 receiver scene_json key_script
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-20}
shift || true
case "$seconds" in
  ''|*[!0-9]*) echo "usage: $0 [SECONDS] [TARGET...]" >&2; exit 2 ;;
esac
targets=("$@")
((${#targets[@]})) || targets=(wire_v1 wire_v2 receiver scene_json key_script)

if ! command -v clang++-14 >/dev/null; then
  echo "clang++-14 is missing: apt-get install clang-14 libclang-rt-14-dev" >&2
  exit 2
fi

start=$SECONDS
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)" >/dev/null
echo "build: $((SECONDS - start)) s"

root=build/fuzz
bin=$root/fuzz
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

failed=()
for t in "${targets[@]}"; do
  exe=$bin/${t}_fuzz
  [ -x "$exe" ] || { echo "$t: no such target ($exe)" >&2; exit 2; }
  work=$root/corpus/$t artifacts=$root/artifacts/$t/ log=$root/logs/$t.log
  mkdir -p "$work" "$artifacts" "$(dirname "$log")"

  # Every saved reproducer must run clean (libFuzzer runs files given by name once each).
  mapfile -t regressions < <(find "fuzz/regressions/$t" -type f 2>/dev/null | sort)
  if ((${#regressions[@]})); then
    if ! "$exe" "${regressions[@]}" > "$root/logs/$t.regressions.log" 2>&1; then
      echo "$t: a regression input fails again (log: $root/logs/$t.regressions.log)"
      grep -E "invariant failed|ERROR:|SUMMARY:|Running:" "$root/logs/$t.regressions.log" | tail -n 6 | sed 's/^/  /'
      failed+=("$t")
    fi
  fi

  dict=()
  [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="fuzz/dict/$t.dict")
  status=0
  "$exe" "$work" "fuzz/corpus/$t" "${dict[@]}" -max_total_time="$seconds" -timeout=25 -print_final_stats=1 \
    -artifact_prefix="$artifacts" > "$log" 2>&1 || status=$?
  done_line=$(grep -E "^#[0-9]+[[:space:]]+DONE" "$log" | tail -n 1 || true)
  rate=$(grep -E "^stat::average_exec_per_sec" "$log" | awk '{print $2}' || true)
  if [ "$status" -eq 0 ]; then
    echo "$t: ${done_line:-no DONE line} (average exec/s: ${rate:-?}; regression inputs: ${#regressions[@]})"
  else
    echo "$t: CRASHED (exit $status; log: $log)"
    grep -E "invariant failed|ERROR:|SUMMARY:|Test unit written|^ +#[0-9]+ 0x" "$log" | head -n 14 | sed 's/^/  /'
    [[ " ${failed[*]} " == *" $t "* ]] || failed+=("$t")
  fi
done

echo "total: $((SECONDS - start)) s"
if ((${#failed[@]})); then
  echo "failed: ${failed[*]}"
  exit 1
fi
