#!/usr/bin/env bash
# The main job: installs the dependencies, builds, and regenerates the paper's Fig. 4 (noise
# sweep, every registered method), writing tables and plots to results/noise_sweep/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/bin/run_experiment noise_sweep.json "$@"
