#!/usr/bin/env bash
# LinuxCNC in the loop, the bench version of tests/linuxcnc (closed_loop scenario) with the demo's
# laser test (targets every 25 mm over the travel, 3 runs): A off → on with LinuxCNC as the
# controller and the virtual machine as the plant, next to the same test in process.
# Usage: bench/linuxcnc_loop.sh [BUILD_DIR] [SEED] [WARMUP_H]   (~4 min; figures in bench/RESULTS.md)
set -euo pipefail
B=${1:-build}; SEED=${2:-1}; WARM=${3:-3}
/usr/bin/python3 tests/linuxcnc/linuxcnc_test.py --scenario closed_loop --seed "$SEED" --warmup-h "$WARM" \
  --laser "--spacing-mm 25 --runs 3" --timeout-s 600 \
  --hal "$B/src/linuxcnc/trueaxis-hal" --plant "$B/src/linuxcnc/trueaxis-hal-plant" --cli "$B/apps/trueaxis/trueaxis"
