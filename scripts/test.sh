#!/usr/bin/env bash
# Installs what is missing, builds everything, runs a bounded fuzz of the
# measurement readers, then every test (CTest's summary is the last output).
# Usage: scripts/test.sh            (build dirs: build/, build-fuzz/)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --all
# Tests, benchmarks and every optional feature are switched on explicitly: scripts/demo.sh
# configures the same build/ with them off or auto-detected, and CMake's cache would otherwise
# keep that (tests not built, none run). TRUEAXIS_ALL_FEATURES=ON fails the configure when a
# feature's library is missing instead of leaving its tests out.
# A compiler cache, when the machine has one, makes rebuilds of unchanged files free.
LAUNCHER=()
# Paths are hashed relative to the checkout, so another clone of the same sources hits the cache too.
if command -v ccache >/dev/null 2>&1; then
  LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$PWD" CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-8G}"
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DTRUEAXIS_BUILD_TESTS=ON -DTRUEAXIS_BUILD_BENCH=ON \
  -DTRUEAXIS_ALL_FEATURES=ON "${LAUNCHER[@]}"
cmake --build build -j"$(nproc)"

# Bounded libFuzzer run of the measurement readers (fuzz/): a separate clang
# build with sanitizers; each fuzzer stops after a fixed number of runs (and at
# most 12 s), so this adds < 30 s of fuzzing. Skipped, saying so, without clang.
if command -v clang++ >/dev/null 2>&1 && command -v clang >/dev/null 2>&1; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DTRUEAXIS_BUILD_FUZZ=ON \
    -DTRUEAXIS_BUILD_TESTS=OFF -DTRUEAXIS_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo "${LAUNCHER[@]}" \
    "-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,address,undefined"
  cmake --build build-fuzz -j"$(nproc)" --target fuzz_measurement_csv fuzz_ecmc_dat
  scratch="$(mktemp -d)"
  trap 'rm -rf "$scratch"' EXIT
  for target in measurement_csv:csv ecmc_dat:ecmc; do
    name="${target%%:*}" corpus="${target##*:}"
    mkdir -p "$scratch/$corpus"
    echo "fuzzing $name (15000 runs)"
    ./build-fuzz/fuzz/fuzz_"$name" "$scratch/$corpus" "fuzz/corpus/$corpus" \
      -runs=15000 -max_len=4096 -max_total_time=12 -print_final_stats=0 2>&1 | tail -n 2
  done
else
  echo "clang/clang++ not found: skipping the libFuzzer run (install clang to enable it)"
fi

cd build
# --no-tests=error: a build that registered no test is a failure, never a green run.
ctest -j"$(nproc)" --output-on-failure --timeout 900 --no-tests=error
