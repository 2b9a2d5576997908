#!/usr/bin/env bash
# Builds ringlab's page: a static site (index.html, the .wasm and wasm-bindgen's JS glue) that
# any web server can host. Usage: web/build.sh [OUT_DIR] (default target/site).
#
# The wasm32 standard library comes from rustup where its target is installed
# (`rustup target add wasm32-unknown-unknown`); where it cannot be (no network beyond the
# package registries) from Debian's rustc-web and rust-web-src (Rust 1.96 and its library's
# source), built with cargo's -Zbuild-std. wasm-bindgen-cli is installed from crates.io at the
# version Cargo.lock pins for the wasm-bindgen crate (the two must match).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$root/target/site}"
cd "$root"

export CARGO_TARGET_DIR="$root/target/web"
target=wasm32-unknown-unknown
cargo_args=(build --profile web --target "$target" -p ringlab-web)
# shellcheck source=../packaging/rust-std.sh
. "$root/packaging/rust-std.sh"
rust_std_for "$target" web/build.sh || exit 1
cargo_args+=("${std_args[@]}")
if [ ${#std_args[@]} -gt 0 ]; then
  # Debian's rustc ships no wasm linker: rustup's toolchain has rust-lld, Debian's lld wasm-ld.
  lld="$(rustc --print sysroot 2>/dev/null)/lib/rustlib/x86_64-unknown-linux-gnu/bin/rust-lld"
  if [ ! -x "$lld" ]; then
    lld="$(command -v wasm-ld || command -v rust-lld || true)"
  fi
  if [ -z "$lld" ]; then
    echo "web/build.sh: no wasm linker: install Debian's lld (apt-get install lld) or rustup's toolchain" >&2
    exit 1
  fi
  export CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_LINKER="$lld"
fi

# wasm-bindgen's own JS glue must be of the version the crate was compiled with.
want="$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)"
if [ -z "$want" ]; then
  echo "web/build.sh: Cargo.lock names no wasm-bindgen version" >&2
  exit 1
fi
if ! wasm-bindgen --version 2>/dev/null | grep -q " $want\$"; then
  echo "web/build.sh: installing wasm-bindgen-cli $want from crates.io"
  # Not --locked: its lock file pins a webpki-roots release the registry no longer serves.
  cargo install --quiet wasm-bindgen-cli --version "$want"
fi

start=$(date +%s)
cargo "${cargo_args[@]}"
mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" \
  "$CARGO_TARGET_DIR/$target/web/ringlab_web.wasm"
cp web/index.html web/worker.js "$out/"
# The sample recording, for links that open it (index.html?recording=sample-ring.csv&fit=1).
cp tests/data/sample-ring.csv "$out/sample-ring.csv"
echo "web/build.sh: site in $out ($(( $(date +%s) - start )) s):"
ls -l "$out"
