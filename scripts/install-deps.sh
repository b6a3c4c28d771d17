#!/usr/bin/env bash
# Installs the Debian packages SEAR builds and tests with, only those missing; silent when all are there.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libode-dev libassimp-dev libeigen3-dev libtinyxml2-dev libstb-dev
  zlib1g-dev                 # assimp's CMake targets link libz.so, which libassimp-dev does not pull in
  libcli11-dev libfmt-dev nlohmann-json3-dev
  libexpat1-dev              # explains in plain words what tinyxml2 refused in a project file (sim/scene/xml_syntax.cpp)
  libgtest-dev libbenchmark-dev
  libembree-dev              # ray casting against the static world (sensors)
  gpsd gpsd-clients          # the NMEA tests check the GPS talker against gpsd
  liblcm-dev liblcm-bin      # LCM: lcm-gen at build time; lcm-logger and lcm-logplayer in the tests
  python3-canmatrix          # decodes SEAR's CAN broadcast through tools/can/sear.dbc in the tests
  qemu-system-x86 busybox-static can-utils  # the vcan tests boot Debian's kernel in a guest (scripts/vcan-guest)
  clang libclang-rt-14-dev   # libFuzzer for the project-file fuzz target
  gcc-avr avr-libc binutils-avr  # the ATmega2560 build of the HAL and the firmware examples
  libsimavr-dev              # the AVR engine (engines/avr) runs AVR images on libsimavr's ATmega2560
  arduino-core-avr arduino-builder  # Arduino sketches: Debian's core (Print, Stream, WString) and the IDE's .ino preprocessing
  gtkwave                    # vcd2fst and fst2vcd read the MCUs' VCD waveforms back in the tests
  sigrok-cli                 # sigrok's UART decoder reads the USART pins of those waveforms in the tests
  parallel                   # GNU parallel runs `sear test --shard K/N` shards in the tests (and over ssh hosts)
  python3-matplotlib         # draws every run's plots (tools/plots/plot_run.py); without it a run only warns
  chromium chromium-driver python3-selenium python3-pil libjs-three libcivetweb-dev  # the browser viewer: civetweb serves it, three.js draws it, headless chromium tests it
  python3-websocket          # the viewer's tests and bench/view_bench.sh talk to `sear view` as a page would
  jq bc                      # bench/timed_runs.sh reads each run's summary.json and adds wall times
  slurm-wlm munge            # scripts/slurm-local.sh: a one-node Slurm runs the `sear test --shard` array job in the tests
  liburdfdom-dev liburdfdom-tools  # URDF robots: urdfdom parses them; the tests hold it against check_urdf
  libqhull-dev               # URDF robots: a body mesh over its triangle budget becomes its convex hull (qhull's reentrant libqhull_r)
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
  [ "$status" = "installed" ] || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "SEAR: installing missing Debian packages: ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "SEAR: these packages are missing and installing them needs root:" >&2
  echo "  apt-get install ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
