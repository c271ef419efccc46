#!/usr/bin/env bash
# Installs what is missing, builds trueaxis and runs the main job.
# Usage: scripts/demo.sh [extra arguments for the demo]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DTRUEAXIS_BUILD_TESTS=OFF -DTRUEAXIS_BUILD_BENCH=OFF
cmake --build build -j"$(nproc)" --target trueaxis
mkdir -p out
./build/apps/trueaxis/trueaxis analyze examples/measurements/x_axis_cold.csv --report out/x_axis_cold.html "$@"
echo "report: out/x_axis_cold.html"
