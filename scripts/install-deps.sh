#!/usr/bin/env bash
# Installs the Debian bookworm packages trueaxis needs to build, test and run.
# Only what is missing is installed; safe to run repeatedly. Needs root (or sudo).
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ccache
  libeigen3-dev libmodbus-dev nlohmann-json3-dev libcli11-dev libtomlplusplus-dev
  libfmt-dev libspdlog-dev libcpp-httplib-dev libsodium-dev libsqlite3-dev
  libxlsxwriter-dev libminizip-dev libpugixml-dev libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-calib3d-dev  # vision: camera calibration, marker images (issue 17)
  linuxcnc-uspace linuxcnc-uspace-dev  # LinuxCNC through HAL: hal.h for trueaxis-hal, the headless simulator of tests/linuxcnc (issue 20)
  mbpoll python3-pymodbus python3-serial-asyncio sqlite3 curl
  libjs-chart.js                                  # web: Chart.js served from the box (no CDN on the shop network, issue 12)
  chromium chromium-driver python3-selenium       # web: the headless-browser test of the pages (issue 12)
  libpqxx-dev postgresql-15  # history on a PostgreSQL server (issue 11); tests start a real server
  libpaho-mqttpp-dev libpaho-mqtt-dev mosquitto mosquitto-clients  # MQTT live values (issue 11); tests start a real broker
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
