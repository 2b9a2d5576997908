#!/usr/bin/env bash
# Builds ringlab's Debian package, target/debian/ringlab_<version>-1_amd64.deb, with cargo-deb
# (the package is described by [package.metadata.deb] in Cargo.toml).
#
#   packaging/linux/build-deb.sh              # release build (a no-op when it is fresh), then the .deb
#   packaging/linux/build-deb.sh --no-build   # the .deb from the binary already in target/release
#
# Any arguments are passed on to `cargo deb`. Works from any folder.
set -euo pipefail

CARGO_DEB_VERSION="3.8.0"

die() {
    echo "build-deb.sh: error: $*" >&2
    exit 1
}

here="$(cd "$(dirname "$0")" && pwd)" || die "cannot find the folder of $0"
repo="$(cd "$here/../.." && pwd)" || die "cannot find the repository above $here"
cd "$repo"
[ -f Cargo.toml ] && grep -q '^\[package.metadata.deb\]' Cargo.toml \
    || die "$repo/Cargo.toml has no [package.metadata.deb] section"

command -v cargo >/dev/null 2>&1 \
    || die "cargo is missing: install Rust with rustup (https://rustup.rs), then run this again"
command -v dpkg >/dev/null 2>&1 \
    || die "dpkg is missing: this script builds a Debian package and must run on Debian or Ubuntu"
# cargo-deb finds the shared libraries' packages ($auto in depends) with dpkg-shlibdeps.
command -v dpkg-shlibdeps >/dev/null 2>&1 \
    || die "dpkg-shlibdeps is missing: $(command -v sudo || true) apt-get install -y dpkg-dev"

have_version="$(cargo deb --version 2>/dev/null || true)"
if [ -z "$have_version" ]; then
    echo "build-deb.sh: cargo-deb is missing; installing cargo-deb $CARGO_DEB_VERSION from crates.io"
    cargo install cargo-deb --locked --version "$CARGO_DEB_VERSION" \
        || die "cargo install cargo-deb --locked --version $CARGO_DEB_VERSION failed"
elif ! printf '%s\n' "$have_version" | grep -q "$CARGO_DEB_VERSION"; then
    echo "build-deb.sh: note: using the installed $have_version (this script is tested with $CARGO_DEB_VERSION)"
fi

for f in packaging/linux/ringlab.desktop \
         packaging/linux/icons/48x48/ringlab.png \
         packaging/linux/icons/256x256/ringlab.png \
         README.md; do
    [ -f "$f" ] || die "$repo/$f is missing (the package ships it)"
done

if command -v desktop-file-validate >/dev/null 2>&1; then
    # Hints (more than one main category: Education;Science) are not errors.
    dfv="$(desktop-file-validate packaging/linux/ringlab.desktop 2>&1 || true)"
    bad="$(printf '%s\n' "$dfv" | grep -v ': hint: ' | grep . || true)"
    [ -z "$bad" ] || die "packaging/linux/ringlab.desktop does not validate: $bad"
fi

start=$(date +%s)
cargo deb "$@" || die "cargo deb $* failed"
end=$(date +%s)

deb="$(ls -t target/debian/ringlab_*.deb 2>/dev/null | head -n 1 || true)"
[ -n "$deb" ] || die "cargo deb ran but left no target/debian/ringlab_*.deb"
size_kib=$(( $(stat -c %s "$deb") / 1024 ))
installed_kib="$(dpkg-deb -f "$deb" Installed-Size)"
echo "build-deb.sh: built $repo/$deb in $((end - start)) s"
echo "build-deb.sh: $size_kib KiB, installed size $installed_kib KiB"
echo "build-deb.sh: Depends: $(dpkg-deb -f "$deb" Depends)"
echo "build-deb.sh: Recommends: $(dpkg-deb -f "$deb" Recommends)"
