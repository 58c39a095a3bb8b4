#!/usr/bin/env bash
# Installs every Debian 12 package dammloam needs to build, test and run.
# Non-interactive and idempotent: packages already present are left alone.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build git pkg-config ca-certificates
  libeigen3-dev libpcl-dev libceres-dev
  libspdlog-dev libfmt-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libstb-dev
  libtbb-dev libnanoflann-dev robin-map-dev
  libreaderwriterqueue-dev libconcurrentqueue-dev
  cyclonedds-dev cyclonedds-tools
  # Second DDS vendor for the interop tests (tests/interop): eProsima Fast DDS 2.9 and its IDL
  # code generator, a Java program (the JRE is only pulled in indirectly, via antlr4).
  libfastrtps-dev libfastcdr-dev fastddsgen default-jre-headless
  libpcap-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  procps
  python3  # tools/check-floors.sh (standard library only)
  libssl-dev
  # tests/system network exposure and DDS Security tests: sockets (ss), certificates and signed
  # governance/permissions (openssl).
  iproute2 openssl
  # libFuzzer targets (tools/fuzz.sh): clang and its runtime (libFuzzer, ASan, UBSan).
  clang-14 libclang-rt-14-dev
  # Recorded bags (io/bag): rosbag2 SQLite storage, MCAP and ROS 1 bag chunk compression
  # (zstd, lz4, bz2), CRC-32.
  libsqlite3-dev libzstd-dev liblz4-dev zlib1g-dev libbz2-dev
  # The ROS 1 bag tests' independent writer (tests/bag/write_ros1_bag.py, run by /usr/bin/python3):
  # Debian's packaging of ROS Noetic's rosbag, its lz4 chunks and the message classes.
  python3-rosbag python3-roslz4 python3-sensor-msgs
  # The bag tests' independent MCAP writer and reader (@mcap/core, tests/bag/node); the bridge
  # tests' Foxglove client (tests/bridge/node) and the bridge page's bundler (tools/bridge/web).
  nodejs
  # dammloam-bridge (tools/bridge): Boost.Beast/Asio, header-only; the page test's browser.
  libboost-dev chromium
)
# Debian's npm; a NodeSource nodejs already ships npm and conflicts with that package.
if ! command -v npm >/dev/null 2>&1; then PACKAGES+=(npm); fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# The npm packages, each pinned by its package-lock.json (into node_modules, which git ignores):
# the bag tests' (tests/bag/node), the bridge tests' (tests/bridge/node: @foxglove/ws-protocol,
# ws, pngjs) and the bridge page's (tools/bridge/web: three.js, esbuild; needed only to rebuild
# the committed bundle site/viewer.js).
install_node_packages() {
  local root dir
  root="$(cd "$(dirname "$0")/.." && pwd)"
  for dir in "$root/tests/bag/node" "$root/tests/bridge/node" "$root/tools/bridge/web"; do
    # npm writes node_modules/.package-lock.json on every install: older than the lock = stale.
    if [ ! -f "$dir/node_modules/.package-lock.json" ] ||
       [ "$dir/package-lock.json" -nt "$dir/node_modules/.package-lock.json" ]; then
      echo "install-deps: npm ci in ${dir#"$root"/}"
      npm ci --prefix "$dir" --no-audit --no-fund
    fi
  done
}

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  install_node_packages
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
install_node_packages
