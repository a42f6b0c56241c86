#!/bin/sh
# Regenerates the committed CI references of the accuracy curves: for every fast config
# experiments/configs/ci/NAME.json, runs it and writes results/reference/NAME/ (summary.csv,
# summary.md, summary.tex, curves.csv, config.resolved.json, run.json; raw/ is removed).
# experiments_regression_test compares fresh runs against these files.
#
# Deliberate by design: run it only when a change of accuracy is intended (a tracker improved,
# a method added or retired, a CI config changed), review `git diff results/reference`, and
# commit the new references together with the change and its reason.
#
#   scripts/update_references.sh [--build DIR] [NAME ...]     (default: every CI config; DIR = build)
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build"
if [ "${1:-}" = "--build" ]; then
  [ $# -ge 2 ] || { echo "update_references.sh: error: --build needs a directory" >&2; exit 2; }
  build=$(cd "$2" && pwd)
  shift 2
fi

cmake --build "$build" --target run_experiment experiments_regression_test >/dev/null
if [ $# -eq 0 ]; then
  set -- $(cd "$root/experiments/configs/ci" && ls *.json | sed 's/\.json$//')
fi

for name in "$@"; do
  config="$root/experiments/configs/ci/$name.json"
  [ -f "$config" ] || { echo "update_references.sh: error: no config $config" >&2; exit 1; }
  out="$root/results/reference/$name"
  "$build/bin/run_experiment" "$config" --out "$out" --no-plots --quiet
  rm -rf "$out/raw"
  echo "update_references.sh: wrote $out"
done

# The new references must pass their own check.
"$build/bin/experiments_regression_test" --gtest_brief=1 >/dev/null || {
  echo "update_references.sh: error: experiments_regression_test fails against the new references" >&2
  echo "  (the ordering check: see build output of $build/bin/experiments_regression_test)" >&2
  exit 1
}
if command -v git >/dev/null 2>&1 && git -C "$root" rev-parse >/dev/null 2>&1; then
  git -C "$root" status --short -- results/reference
fi
echo "update_references.sh: review 'git diff results/reference' and commit it with the reason for the change."
