#!/usr/bin/env bash
# Runs every libFuzzer target of a BUILD_FUZZERS build for a few seconds from its committed seed
# corpus (fuzz/corpus/<target>/). New inputs go to a temporary directory, never into the
# repository; a finding (crash, sanitizer report, an error without its file) fails the script
# and leaves the input in that directory.
# Usage: scripts/fuzz_smoke.sh BUILD_DIR [SECONDS_PER_TARGET]   (default 15 s: 45 s in all)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: scripts/fuzz_smoke.sh BUILD_DIR [SECONDS_PER_TARGET]}
seconds=${2:-15}
work=$(mktemp -d /tmp/slt_fuzz.XXXXXX)
for target in stereo_lines trajectory config; do
  mkdir -p "$work/$target"
  echo "fuzz_smoke: ${target}_fuzzer for ${seconds} s"
  if ! (cd "$work" && "$OLDPWD/$build/bin/${target}_fuzzer" -max_total_time="$seconds" -timeout=10 \
        -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 "$work/$target" "$OLDPWD/fuzz/corpus/$target" \
        > "$work/$target.log" 2>&1); then
    tail -40 "$work/$target.log"
    echo "fuzz_smoke: ${target}_fuzzer found a problem; inputs and log in $work" >&2
    exit 1
  fi
  grep -E "^stat::number_of_executed_units|^#[0-9]+ +DONE" "$work/$target.log" | tail -1 || true
done
rm -rf "$work"
echo "fuzz_smoke: all targets clean"
