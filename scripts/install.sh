#!/usr/bin/env bash
# Installs the patchex library for C and C++ engines: the shared library, the header, a
# pkg-config file and a CMake package config; and the patchex tool (selftest, bench, demo) with
# the scenes and assets its defaults name.
#   scripts/install.sh PREFIX                  builds the release library and tool with cargo,
#                                              then installs them
#   scripts/install.sh PREFIX LIBRARY [TOOL]   installs an already built libpatchex.so (and
#                                              patchex tool) without cargo
# PREFIX then holds
#   lib/libpatchex.so.N (N: the ABI version, its SONAME)  lib/libpatchex.so -> libpatchex.so.N
#   include/patchex.h  lib/pkgconfig/patchex.pc  lib/cmake/patchex/
#   bin/patchex  share/patchex/scenes/  share/patchex/assets/ (with their licences)
# Use it with PKG_CONFIG_PATH=PREFIX/lib/pkgconfig or CMAKE_PREFIX_PATH=PREFIX. A program linked
# through pkg-config finds the library at run time only where the dynamic loader looks: link
# with -Wl,-rpath,PREFIX/lib (pkg-config --variable=libdir patchex) or set LD_LIBRARY_PATH.
# CMake's imported target records the rpath itself.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
prefix="${1:?usage: scripts/install.sh PREFIX [LIBRARY]}"
library="${2:-}"
tool="${3:-}"
if [ -z "$library" ]; then
    (cd "$root" && cargo build --release -p patchex -p patchex-cli)
    library="$root/target/release/libpatchex.so"
    tool="$root/target/release/patchex"
fi
soname="$(readelf -d "$library" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')"
case "$soname" in
    libpatchex.so.[0-9]*) ;;
    *) echo "install.sh: $library has SONAME '$soname', not libpatchex.so.N" >&2; exit 1 ;;
esac
mkdir -p "$prefix"
prefix="$(cd "$prefix" && pwd)"
version="$(sed -n 's/^version = "\(.*\)"/\1/p' "$root/Cargo.toml" | head -1)"
install -Dm755 "$library" "$prefix/lib/$soname"
ln -sfn "$soname" "$prefix/lib/libpatchex.so"
install -Dm644 "$root/include/patchex.h" "$prefix/include/patchex.h"
mkdir -p "$prefix/lib/pkgconfig" "$prefix/lib/cmake/patchex"
sed -e "s|@PREFIX@|$prefix|" -e "s|@VERSION@|$version|" \
    "$root/packaging/patchex.pc.in" > "$prefix/lib/pkgconfig/patchex.pc"
sed -e "s|@SONAME@|$soname|" \
    "$root/packaging/patchexConfig.cmake" > "$prefix/lib/cmake/patchex/patchexConfig.cmake"
cat > "$prefix/lib/cmake/patchex/patchexConfigVersion.cmake" <<VERSION
set(PACKAGE_VERSION "$version")
if(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
endif()
VERSION
if [ -n "$tool" ]; then
    install -Dm755 "$tool" "$prefix/bin/patchex"
    mkdir -p "$prefix/share/patchex/scenes"
    install -m644 "$root"/scenes/*.toml "$prefix/share/patchex/scenes/"
    rm -rf "$prefix/share/patchex/assets"
    cp -r "$root/assets" "$prefix/share/patchex/assets"
fi
echo "installed patchex $version ($soname${tool:+ and the patchex tool}) into $prefix"
