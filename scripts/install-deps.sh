#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file install-deps.sh
# @brief Installs the Debian 12 packages xrsc needs, only when something is missing.
#
# Lavapipe with ray-tracing pipelines needs Mesa >= 24.1; Debian 12's own Mesa is 22.3,
# so bookworm-backports is added and mesa-vulkan-drivers is pinned from it.
set -euo pipefail

PKGS=(
  build-essential cmake pkg-config clang libclang-rt-14-dev
  libvulkan-dev vulkan-validationlayers glslang-tools spirv-tools
  libglfw3-dev libx11-dev libcglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libpng-dev
  libopenexr-dev
  libopenxr-dev libopenxr-loader1 libopenxr-utils openxr-layer-corevalidation
  xvfb xauth gnuplot-nox mesa-vulkan-drivers
  libdraco-dev assimp-testmodels
  libmeshoptimizer-dev
  slurm-wlm munge
)
# slurm-wlm, munge: the one-node Slurm that test_sweep_slurm starts (scripts/slurm/, issue 24).
# libdraco-dev: KHR_draco_mesh_compression (optional at build time: CMake XRSC_DRACO);
# libmeshoptimizer-dev: EXT_meshopt_compression (optional at build time: CMake XRSC_MESHOPT);
# assimp-testmodels: third-party glTF 2.0 files for test_gltf_assimp (which skips without it).
# libopenexr-dev: OpenEXR 3.1's C library (OpenEXRCore) for `xrsc --write exr`. ffmpeg (for
# `xrsc --video`) is optional and deliberately not installed here.
MESA_MIN=24.1

sudo_() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
mesa_ver=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
mesa_ok=0
if [ -n "$mesa_ver" ] && dpkg --compare-versions "$mesa_ver" ge "$MESA_MIN"; then mesa_ok=1; fi

if [ ${#missing[@]} -eq 0 ] && [ $mesa_ok -eq 1 ]; then
  echo "install-deps: all packages present (mesa-vulkan-drivers $mesa_ver)"
  exit 0
fi

. /etc/os-release
if [ "${VERSION_CODENAME:-}" != "bookworm" ]; then
  echo "install-deps: warning: written for Debian 12 (bookworm), this is ${PRETTY_NAME:-unknown}" >&2
fi

export DEBIAN_FRONTEND=noninteractive
bp=/etc/apt/sources.list.d/xrsc-bookworm-backports.list
if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "deb http://deb.debian.org/debian bookworm-backports main" | sudo_ tee "$bp" >/dev/null
fi
pin=/etc/apt/preferences.d/xrsc-mesa-backports
if [ ! -f "$pin" ]; then
  sudo_ tee "$pin" >/dev/null <<'PIN'
Package: mesa-vulkan-drivers libllvm19 libdrm* libgbm1 libglapi-mesa libgl1-mesa-dri libegl-mesa0 libglx-mesa0 mesa-libgallium libxcb-randr0 libxcb-dri3-0 libxcb-present0 libxcb-sync1 libxcb-xfixes0 libxshmfence1 libwayland-client0 libz3-4
Pin: release n=bookworm-backports
Pin-Priority: 990
PIN
fi
sudo_ apt-get update -q
sudo_ apt-get install -y -q --no-install-recommends "${PKGS[@]}"
sudo_ apt-get install -y -q --no-install-recommends -t bookworm-backports mesa-vulkan-drivers
mesa_ver=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers)
if ! dpkg --compare-versions "$mesa_ver" ge "$MESA_MIN"; then
  echo "install-deps: error: mesa-vulkan-drivers $mesa_ver < $MESA_MIN (no lavapipe ray tracing)" >&2
  exit 1
fi
echo "install-deps: done (mesa-vulkan-drivers $mesa_ver)"
