#!/usr/bin/env bash
# A cheap check that ringlab still compiles for Windows: `cargo check` of the app crate (library
# and binary) for x86_64-pc-windows-gnu, warnings as errors. Nothing is linked, so MinGW is not
# needed; the same choice of toolchain as build-windows.sh (rustup's target std, or Debian's
# rustc-web with -Zbuild-std). Its own target dir, target/windows-check.
#
#   packaging/windows/check-windows.sh
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
target=x86_64-pc-windows-gnu
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target/windows-check}"

die() { echo "check-windows.sh: $*" >&2; exit 1; }

command -v cargo >/dev/null 2>&1 || die "cargo is missing: install Rust (https://rustup.rs)"
cd "$root"

if command -v rustup >/dev/null 2>&1 &&
    rustup target list --installed 2>/dev/null | grep -qx "$target"; then
    check=(cargo check --target "$target" -p ringlab --lib --bins)
else
    if [ ! -x /usr/bin/rustc ] || [ ! -d /usr/lib/rustlib/src/rust/library ]; then
        sudo_prefix=""
        [ "$(id -u)" = 0 ] || sudo_prefix=$(command -v sudo || true)
        command -v apt-get >/dev/null 2>&1 ||
            die "no $target std: run 'rustup target add $target' (or install Debian's rustc-web and rust-web-src)"
        echo "check-windows.sh: installing Debian's rustc-web and rust-web-src" >&2
        if ! { $sudo_prefix apt-get update -q &&
            $sudo_prefix apt-get install -y -q rustc-web rust-web-src; }; then
            die "could not install rustc-web and rust-web-src"
        fi
    fi
    export RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1
    check=(cargo check --target "$target" -p ringlab --lib --bins "-Zbuild-std=std,panic_abort")
fi

start=$(date +%s)
echo "check-windows.sh: ${check[*]}" >&2
RUSTFLAGS="${RUSTFLAGS:-} -D warnings" "${check[@]}"
echo "check-windows.sh: ok in $(($(date +%s) - start)) s" >&2
