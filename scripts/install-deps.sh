#!/usr/bin/env bash
# Installs the Debian 12 packages skelgrasp needs to build and test, and nothing when all are
# present (idempotent). Runs as root, or through sudo when available.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libpcl-dev libcgal-dev libgmp-dev libmpfr-dev libfcl-dev liboctomap-dev
  libopencv-dev libpng-dev libqhull-dev libtbb-dev libhdf5-dev liburdfdom-dev libassimp-dev
  nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev libgtest-dev libbenchmark-dev
  libcurl4-openssl-dev libglpk-dev libyaml-cpp-dev libjs-three libnanoflann-dev
  # The physics judge (physics/): Bullet and its extras (HACD convex decomposition).
  libbullet-dev libbullet-extras-dev
  # The Python module (python/, built by default) against Debian's interpreter.
  pybind11-dev python3-dev python3-numpy
)
for option in "$@"; do
  case "$option" in
    # `make test` also runs GNU parallel and Slurm (sharded evaluation; the test starts its own
    # munged, slurmctld and slurmd), a headless browser (the report's 3D view) and pytest (the
    # Python module's tests, tests/python/).
    --test) packages+=(parallel slurm-wlm munge chromium python3-pytest) ;;
    # `make fuzz` also needs clang with its libFuzzer runtime.
    --fuzz) packages+=(clang libclang-rt-14-dev llvm) ;;
    *) echo "install-deps: error: unknown option $option (known: --test, --fuzz)" >&2; exit 2 ;;
  esac
done

missing=()
for pkg in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
  else
    echo "install-deps: error: not root and sudo is unavailable; install as root: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
# Without recommends: with them a fresh machine pulled in ~500 packages (a modem manager, mDNS
# daemons, ...). What the build and tests use of the recommends is covered by the list itself:
# cmake's gcc and make come with build-essential (which also brings gcc's libc6-dev); chromium's
# libgl1-mesa-dri is not used (the browser test renders WebGL with chromium's own SwiftShader),
# its fonts-liberation is replaced by the font fontconfig depends on; libcurl's ca-certificates
# only matter for https downloads, which the tests do not make (they serve files locally).
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
