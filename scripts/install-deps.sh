#!/usr/bin/env bash
# Installs the Debian bookworm packages trueaxis needs to build, test and run.
# Only what is missing is installed; safe to run repeatedly. Needs root (or sudo).
set -euo pipefail

# Usage: scripts/install-deps.sh [--demo | --hal | --all]
#   --demo  what `scripts/demo.sh` needs: the compiler and build tools and the core libraries
#           (the optional features — vision, PostgreSQL, MQTT, LinuxCNC — are then left out of the build)
#   --hal   what the lean build of the LinuxCNC HAL programs needs (cmake -DTRUEAXIS_ONLY_HAL=ON,
#           docs/linuxcnc.md): the demo's libraries without cpp-httplib and Chart.js, with linuxcnc-uspace-dev
#   --all   (default) everything the tests need: every optional feature, the servers and tools the
#           tests start (PostgreSQL, mosquitto, LinuxCNC, headless Chromium), clang for the fuzzers
profile=all
case "${1:-}" in
  --demo) profile=demo ;;
  --hal) profile=hal ;;
  --all|"") profile=all ;;
  *) echo "usage: $0 [--demo | --hal | --all]" >&2; exit 2 ;;
esac

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ccache
  libeigen3-dev libmodbus-dev nlohmann-json3-dev libcli11-dev libtomlplusplus-dev
  libfmt-dev libcpp-httplib-dev libsodium-dev libsqlite3-dev
  libxlsxwriter-dev libminizip-dev libpugixml-dev
  libjs-chart.js                                  # web: Chart.js served from the box (no CDN on the shop network)
)
if [ "$profile" = hal ]; then
  lean=(linuxcnc-uspace-dev)
  for p in "${PACKAGES[@]}"; do
    case "$p" in libcpp-httplib-dev|libjs-chart.js) ;; *) lean+=("$p") ;; esac
  done
  PACKAGES=("${lean[@]}")
fi
if [ "$profile" = all ]; then
  PACKAGES+=(
    libgtest-dev libgmock-dev libbenchmark-dev
    clang libclang-rt-14-dev                        # the libFuzzer run of the measurement readers
    libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-calib3d-dev  # vision: camera calibration, marker images
    linuxcnc-uspace linuxcnc-uspace-dev  # LinuxCNC through HAL: hal.h for trueaxis-hal, the headless simulator of tests/linuxcnc
    mbpoll python3-pymodbus python3-serial-asyncio sqlite3 curl
    chromium chromium-driver python3-selenium       # web: the headless-browser test of the pages
    libpqxx-dev postgresql-15  # history on a PostgreSQL server; tests start a real server
    libpaho-mqttpp-dev libpaho-mqtt-dev mosquitto mosquitto-clients  # MQTT live values; tests start a real broker
  )
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages of the $profile profile present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
