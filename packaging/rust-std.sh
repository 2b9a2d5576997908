# Sourced by web/build.sh and packaging/windows/{build,check}-windows.sh: the standard library
# for a cross target, chosen once for all three.
#
#   rust_std_for TARGET WHO   # WHO: the calling script's name, for its messages
#
# Where rustup has TARGET's std (`rustup target add TARGET`) cargo builds the plain way and
# std_args is empty. Otherwise (these machines reach no rustup server) Debian's rustc-web, whose
# std source comes in rust-web-src (both installed with apt-get where missing), with cargo's
# -Zbuild-std: RUSTC and RUSTC_BOOTSTRAP are exported and std_args holds the flag to add.
# Returns non-zero, having said why, where neither can be had.
rust_std_for() {
    local target=$1 who=$2 sudo_prefix=""
    std_args=()
    if command -v rustup >/dev/null 2>&1 &&
        rustup target list --installed 2>/dev/null | grep -qx "$target"; then
        echo "$who: rustup's $target standard library" >&2
        return 0
    fi
    if [ ! -x /usr/bin/rustc ] || [ ! -d /usr/lib/rustlib/src/rust/library ]; then
        if ! command -v apt-get >/dev/null 2>&1; then
            echo "$who: no $target standard library: run 'rustup target add $target' (or install Debian's rustc-web and rust-web-src)" >&2
            return 1
        fi
        [ "$(id -u)" = 0 ] || sudo_prefix=$(command -v sudo || true)
        echo "$who: no $target standard library: installing Debian's rustc-web and rust-web-src" >&2
        if ! { $sudo_prefix apt-get update -qq &&
            DEBIAN_FRONTEND=noninteractive $sudo_prefix apt-get install -y -qq \
                --no-install-recommends rustc-web rust-web-src; }; then
            echo "$who: could not install rustc-web and rust-web-src" >&2
            return 1
        fi
    fi
    echo "$who: Debian's rustc-web ($(/usr/bin/rustc --version)), the standard library built here (-Zbuild-std)" >&2
    export RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1
    std_args=("-Zbuild-std=std,panic_abort")
}
