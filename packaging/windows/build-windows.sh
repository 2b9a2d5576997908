#!/usr/bin/env bash
# ringlab.exe and its installer, cross-built on Debian for x86_64-pc-windows-gnu (MinGW-w64).
#
#   packaging/windows/build-windows.sh              # the .exe, then ringlab-setup.exe
#   packaging/windows/build-windows.sh --exe-only   # the .exe alone
#   packaging/windows/build-windows.sh --installer-only  # the installer of dist/ringlab.exe
#
# Output in target/windows/dist/: ringlab.exe (stripped) and ringlab-setup.exe.
# Where rustup has the target's std (`rustup target add x86_64-pc-windows-gnu`) it builds the
# plain way; otherwise with Debian's rustc-web (a rustc whose std source comes in rust-web-src)
# and cargo's -Zbuild-std, which compiles std for the target from that source.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
target=x86_64-pc-windows-gnu
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target/windows}"
dist="$CARGO_TARGET_DIR/dist"

exe_only=0
installer_only=0
for arg in "$@"; do
    case "$arg" in
        --exe-only) exe_only=1 ;;
        --installer-only) installer_only=1 ;;
        -h | --help) sed -n '2,11p' "$0"; exit 0 ;;
        *) echo "build-windows.sh: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
    esac
done

die() { echo "build-windows.sh: $*" >&2; exit 1; }

sudo_prefix=""
if [ "$(id -u)" != 0 ]; then
    sudo_prefix=$(command -v sudo || true)
fi

# need COMMAND PACKAGE: install PACKAGE with apt-get where COMMAND is missing.
need() {
    command -v "$1" >/dev/null 2>&1 && return 0
    command -v apt-get >/dev/null 2>&1 ||
        die "'$1' is missing and there is no apt-get to install it: install '$2' (Debian's name)"
    echo "build-windows.sh: '$1' is missing, installing Debian's '$2'" >&2
    if ! { $sudo_prefix apt-get update -q && $sudo_prefix apt-get install -y -q "$2"; }; then
        die "could not install '$2' (needed for '$1')"
    fi
    command -v "$1" >/dev/null 2>&1 || die "'$1' still missing after installing '$2'"
}

[ "$exe_only" = 1 ] || need makensis nsis
# shellcheck source=../rust-std.sh
. "$here/../rust-std.sh"
cd "$root"

# The .exe: cargo, then a stripped copy in dist/.
build_exe() {
    local build start built
    command -v cargo >/dev/null 2>&1 || die "cargo is missing: install Rust (https://rustup.rs)"
    need x86_64-w64-mingw32-gcc gcc-mingw-w64-x86-64
    export CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER=x86_64-w64-mingw32-gcc

    # Debian's rustc-web is new enough for the crate's rust-version (1.95) on bookworm.
    rust_std_for "$target" build-windows.sh || exit 1
    build=(cargo build --release --target "$target" --bin ringlab "${std_args[@]}")

    start=$(date +%s)
    echo "build-windows.sh: ${build[*]} (CARGO_TARGET_DIR=$CARGO_TARGET_DIR)" >&2
    "${build[@]}"
    echo "build-windows.sh: cargo took $(($(date +%s) - start)) s" >&2

    built="$CARGO_TARGET_DIR/$target/release/ringlab.exe"
    [ -f "$built" ] || die "the build reported success but $built is missing"
    mkdir -p "$dist"
    x86_64-w64-mingw32-strip -o "$dist/ringlab.exe" "$built"
    echo "build-windows.sh: $dist/ringlab.exe ($(stat -c %s "$dist/ringlab.exe") bytes; unstripped $(stat -c %s "$built"))" >&2
}

if [ "$installer_only" = 0 ]; then
    build_exe
    [ "$exe_only" = 1 ] && exit 0
fi

[ -f "$dist/ringlab.exe" ] || die "$dist/ringlab.exe is missing: build it first (without --installer-only)"

version=$(sed -n 's/^version = "\([^"]*\)".*/\1/p' "$root/Cargo.toml" | head -n 1)
[ -n "$version" ] || die "no version = \"...\" found in $root/Cargo.toml"
icon_def=()
[ -f "$here/ringlab.ico" ] && icon_def=("-DICON=$here/ringlab.ico")
makensis -V2 -INPUTCHARSET UTF8 \
    "-DVERSION=$version" \
    "-DEXE=$dist/ringlab.exe" \
    "${icon_def[@]}" \
    "-DOUTFILE=$dist/ringlab-setup.exe" \
    "$here/ringlab.nsi"
echo "build-windows.sh: $dist/ringlab-setup.exe ($(stat -c %s "$dist/ringlab-setup.exe") bytes, version $version)" >&2
