#!/usr/bin/env bash
# A check, without linking, that ringlab still builds for Windows; the same choice of toolchain
# as build-windows.sh (rustup's target std, or Debian's rustc-web with -Zbuild-std). Its own
# target dir, target/windows-check. Of MinGW only dlltool is needed (binutils-mingw-w64-x86-64:
# the standard library built here for windows-gnu calls it, even to check).
#
#   packaging/windows/check-windows.sh          # `cargo check` of the app crate (library and
#                                               # binary) for x86_64-pc-windows-gnu (minutes)
#   packaging/windows/check-windows.sh --quick  # what only Windows compiles, in a minute or two:
#       the console code (src/cli/windows_console.rs) checked for the target against the
#       windows-sys the app's Cargo.toml names, and the installer script (ringlab.nsi) compiled
#       by makensis around a stand-in program. CI runs this one (.ci/run); the rest of the app
#       is the same code on every platform, which the Linux build already checks.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
target=x86_64-pc-windows-gnu
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target/windows-check}"

die() { echo "check-windows.sh: $*" >&2; exit 1; }

quick=0
case "${1:-}" in
    "") ;;
    --quick) quick=1 ;;
    *) die "unknown argument '$1' (expected nothing or --quick)" ;;
esac

command -v cargo >/dev/null 2>&1 || die "cargo is missing: install Rust (https://rustup.rs)"
cd "$root"

# Debian's packages this check lacks, installed with apt-get (as root, or through sudo).
apt_install() {
    local sudo_prefix=""
    [ "$(id -u)" = 0 ] || sudo_prefix=$(command -v sudo || true)
    command -v apt-get >/dev/null 2>&1 || die "missing: $* (install them, or rustup's $target target)"
    echo "check-windows.sh: installing $*" >&2
    { $sudo_prefix apt-get update -qq &&
        DEBIAN_FRONTEND=noninteractive $sudo_prefix apt-get install -y -qq --no-install-recommends "$@"; } ||
        die "could not install $*"
}

missing=()
[ "$quick" = 0 ] || command -v makensis >/dev/null 2>&1 || missing+=(nsis)
# shellcheck source=../rust-std.sh
. "$here/../rust-std.sh"
rust_std_for "$target" check-windows.sh || exit 1
check=(cargo check --target "$target" "${std_args[@]}")
# std built for windows-gnu links its raw-dylib imports through MinGW's dlltool, even to check.
[ ${#std_args[@]} -eq 0 ] || command -v x86_64-w64-mingw32-dlltool >/dev/null 2>&1 ||
    missing+=(binutils-mingw-w64-x86-64)
[ ${#missing[@]} -eq 0 ] || apt_install "${missing[@]}"

# The quick check's crate: the console module alone over the app's own windows-sys line, with the
# app's Cargo.lock so that the same windows-sys release is checked.
console_crate() {
    local dir="$CARGO_TARGET_DIR/console-crate" dep
    dep=$(grep -m1 '^windows-sys *=' "$root/Cargo.toml") ||
        die "Cargo.toml names no windows-sys dependency (the console code needs it)"
    mkdir -p "$dir"
    printf '%s\n' '[package]' 'name = "ringlab-windows-console-check"' 'version = "0.0.0"' \
        'edition = "2024"' 'publish = false' '' '[lib]' 'path = "lib.rs"' '' '[workspace]' '' \
        '[dependencies]' "$dep" >"$dir/Cargo.toml"
    printf '%s\n' '#![deny(warnings)]' "#[path = \"$root/src/cli/windows_console.rs\"]" \
        'pub mod windows_console;' >"$dir/lib.rs"
    cp "$root/Cargo.lock" "$dir/Cargo.lock"
    echo "$dir"
}

installer_script() {
    local stand_in="$CARGO_TARGET_DIR/stand-in.exe" version
    version=$(sed -n 's/^version = "\(.*\)"/\1/p' "$root/Cargo.toml" | head -n1)
    printf 'not a program: check-windows.sh --quick compiles the installer around it\n' >"$stand_in"
    makensis -V2 -INPUTCHARSET UTF8 "-DVERSION=$version" "-DEXE=$stand_in" \
        "-DICON=$here/ringlab.ico" "-DOUTFILE=$CARGO_TARGET_DIR/ringlab-setup-check.exe" \
        "$here/ringlab.nsi" >/dev/null || die "makensis failed on ringlab.nsi"
}

if [ "$quick" = 1 ]; then
    start=$(date +%s)
    mkdir -p "$CARGO_TARGET_DIR"
    installer_script
    crate=$(console_crate)
    echo "check-windows.sh: ${check[*]} (src/cli/windows_console.rs alone)" >&2
    (cd "$crate" && RUSTFLAGS="${RUSTFLAGS:-} -D warnings" "${check[@]}")
    echo "check-windows.sh: quick check ok in $(($(date +%s) - start)) s" >&2
    exit 0
fi
check+=(-p ringlab --lib --bins)

start=$(date +%s)
echo "check-windows.sh: ${check[*]}" >&2
RUSTFLAGS="${RUSTFLAGS:-} -D warnings" "${check[@]}"
echo "check-windows.sh: ok in $(($(date +%s) - start)) s" >&2
