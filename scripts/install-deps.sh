#!/usr/bin/env bash
# Installs what building and testing patchex needs on Debian: the Vulkan loader and headers,
# Mesa's lavapipe (a CPU Vulkan driver), the Khronos validation layers, a C++ compiler, CMake
# and glslang (for the C++ engine example), and a font for the plots of `patchex bench`.
# Further packages may be named as arguments. Does nothing when everything is already there.
set -euo pipefail
packages=(mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers g++ binutils pkg-config cmake glslang-tools fonts-dejavu-core "$@")
missing=()
for package in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    sudo_cmd=""
    [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
    $sudo_cmd apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}"
fi
