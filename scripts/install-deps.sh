#!/usr/bin/env bash
# Installs the Debian packages Hemirad needs that are missing; idempotent and quiet when nothing is.
set -euo pipefail

packages=(
  cmake g++ make pkg-config
  libembree-dev libeigen3-dev libglm-dev libtinyobjloader-dev doctest-dev libstb-dev
  libglfw3-dev libepoxy-dev libegl-dev libegl-mesa0 libgl-dev libosmesa6-dev libimgui-dev
  xvfb python3-matplotlib
)

# `install-deps.sh fuzz` adds clang and its fuzzer/sanitizer runtime for `make fuzz`.
if [ "${1:-}" = "fuzz" ]; then packages+=(clang libclang-rt-14-dev libomp-dev); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
if ! $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/tmp/hemirad-apt.log 2>&1; then
  $sudo apt-get update -qq >/tmp/hemirad-apt.log 2>&1 || true
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >>/tmp/hemirad-apt.log 2>&1 || {
    echo "install-deps: apt-get failed; see /tmp/hemirad-apt.log" >&2; tail -20 /tmp/hemirad-apt.log >&2; exit 1; }
fi
