#!/usr/bin/env bash
# Installs what is missing, builds the demo and runs the main job: the
# end-to-end demo (calibration campaign on the virtual machine, model fit, a
# working day with the real-time compensator in its loop, ISO 230-2 before /
# after) — report in out/demo/report.html.
# Usage: scripts/demo.sh [extra arguments for `trueaxis demo`, e.g. --fast or --seed 7]
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what the demo needs: the optional features (vision, PostgreSQL, MQTT, LinuxCNC) are built
# when their libraries are already there (scripts/test.sh installs them), else left out.
bash scripts/install-deps.sh --demo
# A compiler cache, when the machine has one, makes rebuilds of unchanged files free.
LAUNCHER=()
# Paths are hashed relative to the checkout, so another clone of the same sources hits the cache too.
if command -v ccache >/dev/null 2>&1; then
  LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$PWD" CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-8G}"
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DTRUEAXIS_BUILD_TESTS=OFF -DTRUEAXIS_BUILD_BENCH=OFF \
  -DTRUEAXIS_ALL_FEATURES=OFF "${LAUNCHER[@]}"
# Only the demo (trueaxis-demo: the `demo` command over only the modules it runs, about a quarter
# of the compile of every command). Every other command: `cmake --build build --target trueaxis`.
cmake --build build -j"$(nproc)" --target trueaxis-demo
./build/apps/trueaxis/trueaxis-demo demo --out out/demo "$@"
echo "report: out/demo/report.html"
echo "every other command: cmake --build build --target trueaxis, then ./build/apps/trueaxis/trueaxis --help (docs/tour.md)"
