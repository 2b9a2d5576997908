#!/usr/bin/env bash
# Tests ringlab's .deb on a clean Debian bookworm: a fresh root made by debootstrap, the package
# installed there with apt as a teacher would (`apt install ./ringlab_*.deb`), then `ringlab`
# started as an ordinary user under Xvfb with Mesa's software Vulkan (lavapipe), a screenshot
# of the screen taken, and the window looked for. Prints PASS or FAIL (exit status 0 or 1).
#
#   sudo packaging/linux/test-deb.sh [PATH/TO/ringlab_*.deb]
#
# Without an argument it tests the newest target/debian/ringlab_*.deb. Needs root (debootstrap,
# chroot, mount). Everything it makes lies under target/deb-test/ (or $RINGLAB_DEB_TEST_DIR):
#   base/        the clean root debootstrap made, kept so that a second run skips debootstrap
#   apt-cache/   the packages apt downloaded, kept for the same reason
#   root/        this run's root, a fresh copy of base/ (left after the run for a look inside)
#   screenshot.png, xwininfo.txt, ringlab.log, install.log   what this run saw
# Settings (environment): DEBIAN_MIRROR (default: the host's apt mirror of Debian, else
# http://deb.debian.org/debian), DEBIAN_SECURITY_MIRROR (default: the mirror's URL + "-security"),
# RINGLAB_TEST_WAIT (seconds the window is given, default 25),
# RINGLAB_TEST_DISPLAY (the X display number, default 99 or the next free one).
set -euo pipefail

die() {
    echo "test-deb.sh: error: $*" >&2
    echo "FAIL"
    exit 1
}
say() { echo "test-deb.sh: $*"; }

here="$(cd "$(dirname "$0")" && pwd)" || die "cannot find the folder of $0"
repo="$(cd "$here/../.." && pwd)" || die "cannot find the repository above $here"
cd "$repo"

[ "$(id -u)" = 0 ] || die "must run as root (debootstrap, chroot and mount need it): sudo $0 $*"
for tool in debootstrap chroot mount umount mountpoint findmnt dpkg-deb; do
    command -v "$tool" >/dev/null 2>&1 || die "$tool is missing: apt-get install -y debootstrap util-linux dpkg coreutils"
done

deb="${1:-}"
if [ -z "$deb" ]; then
    deb="$(ls -t target/debian/ringlab_*.deb 2>/dev/null | head -n 1 || true)"
    [ -n "$deb" ] || die "no target/debian/ringlab_*.deb: build it first with packaging/linux/build-deb.sh"
fi
[ -f "$deb" ] || die "the package $deb is missing"
deb="$(cd "$(dirname "$deb")" && pwd)/$(basename "$deb")"

work="${RINGLAB_DEB_TEST_DIR:-$repo/target/deb-test}"
base="$work/base"
root="$work/root"
aptcache="$work/apt-cache"
wait_s="${RINGLAB_TEST_WAIT:-25}"
mkdir -p "$work" "$aptcache"

# The Debian mirror this machine's apt uses (deb822 .sources or one-line .list files).
host_mirror() {
    local f url
    for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources; do
        [ -f "$f" ] || continue
        url="$(grep -vE '^[[:space:]]*#' "$f" 2>/dev/null | grep -oE 'https?://[^ ]+/debian/?( |$)' | head -n 1 | tr -d ' ' || true)"
        if [ -n "$url" ]; then
            echo "${url%/}"
            return 0
        fi
    done
    return 1
}
mirror="${DEBIAN_MIRROR:-$(host_mirror || echo http://deb.debian.org/debian)}"
security_mirror="${DEBIAN_SECURITY_MIRROR:-${mirror}-security}"
say "Debian mirror: $mirror (security: $security_mirror)"

t0=$(date +%s)

# --- cleaning up: whatever this run started or mounted, in reverse order ----------------------
pids=()
mounts=()
cleanup() {
    local i p m
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
        p="${pids[$i]}"
        kill "$p" 2>/dev/null || true
    done
    sleep 1
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
        p="${pids[$i]}"
        kill -9 "$p" 2>/dev/null || true
    done
    for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do
        m="${mounts[$i]}"
        if mountpoint -q "$m"; then
            umount "$m" 2>/dev/null || umount -l "$m" 2>/dev/null || echo "test-deb.sh: could not unmount $m" >&2
        fi
    done
}
trap cleanup EXIT
trap 'exit 130' INT TERM

mount_in() { # mount_in TARGET-IN-ROOT mount-arguments...
    local target="$root$1"
    shift
    mkdir -p "$target"
    mount "$@" "$target" || die "mount $* $target failed"
    mounts+=("$target")
}

# Refuses to delete a root that still has something mounted inside (that would delete the host's).
assert_unmounted() {
    if findmnt -rn -o TARGET | grep -q "^$1\(/\|$\)"; then
        die "something is still mounted under $1 (see findmnt); unmount it, then run again"
    fi
}

# --- a clean bookworm, made once ----------------------------------------------------------------
if [ ! -f "$base/.ringlab-debootstrap-done" ]; then
    say "making a clean Debian bookworm with debootstrap (once; kept in $base)"
    assert_unmounted "$base"
    rm -rf --one-file-system "$base"
    mkdir -p "$work/debootstrap-cache"
    debootstrap --variant=minbase --cache-dir="$work/debootstrap-cache" bookworm "$base" "$mirror" \
        > "$work/debootstrap.log" 2>&1 \
        || die "debootstrap failed (see $work/debootstrap.log)"
    touch "$base/.ringlab-debootstrap-done"
fi
t_base=$(date +%s)

say "a fresh root for this run: $root"
assert_unmounted "$root"
rm -rf --one-file-system "$root"
cp -a "$base" "$root" || die "cp -a $base $root failed"
rm -f "$root/.ringlab-debootstrap-done"

cat > "$root/etc/apt/sources.list" <<EOF
deb $mirror bookworm main
deb $mirror bookworm-updates main
deb $security_mirror bookworm-security main
EOF
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
printf '#!/bin/sh\nexit 101\n' > "$root/usr/sbin/policy-rc.d" # no services started by apt
chmod 755 "$root/usr/sbin/policy-rc.d"

mount_in /proc -t proc proc
mount_in /sys -t sysfs sysfs
mount_in /dev --bind /dev
mount_in /dev/pts -t devpts devpts -o newinstance,ptmxmode=0666
mount_in /dev/shm -t tmpfs tmpfs -o mode=1777
mount_in /var/cache/apt/archives --bind "$aptcache"

in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin \
    HOME=/root LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive "$@"; }

# --- the package installed as a teacher installs it ---------------------------------------------
cp "$deb" "$root/tmp/" || die "cannot copy $deb into $root/tmp"
debname="$(basename "$deb")"
say "apt-get update"
in_root apt-get update > "$work/install.log" 2>&1 || die "apt-get update failed in the chroot (see $work/install.log)"
sum_installed_kib() { in_root dpkg-query -W -f='${Installed-Size}\n' | awk '{ s += $1 } END { print s + 0 }'; }
would_install() { # would_install [apt flags]: the packages apt would install with the .deb
    chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 \
        sh -c "cd /tmp && apt-get install -s $* ./$debname" | awk '/^Inst / { print $2 }'
}
list_with="$(would_install)" || die "apt-get install -s ./$debname failed in the chroot"
list_without="$(would_install --no-install-recommends)" || die "apt-get install -s --no-install-recommends ./$debname failed"
n_with="$(printf '%s\n' "$list_with" | grep -c . || true)"
n_without="$(printf '%s\n' "$list_without" | grep -c . || true)"
# What the packages other than ringlab would take without Recommends (from apt's lists).
kib_deps_min="$(printf '%s\n' "$list_without" | grep -vx ringlab \
    | xargs -r chroot "$root" /usr/bin/env -i PATH=/usr/bin:/bin apt-cache show --no-all-versions \
    | awk '/^Installed-Size:/ { s += $2 } END { print s + 0 }')"
kib_before="$(sum_installed_kib)"
say "apt-get install -y ./$debname (with its Recommends, as apt does by default): $n_with packages ($n_without without Recommends)"
t_inst0=$(date +%s)
chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root \
    LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive sh -c "cd /tmp && apt-get install -y ./$debname" \
    >> "$work/install.log" 2>&1 || die "apt-get install ./$debname failed in the clean root (see $work/install.log)"
t_inst1=$(date +%s)

in_root sh -c 'test -x /usr/bin/ringlab' || die "/usr/bin/ringlab is not there after the install"
for f in /usr/share/applications/ringlab.desktop \
         /usr/share/icons/hicolor/48x48/apps/ringlab.png \
         /usr/share/icons/hicolor/256x256/apps/ringlab.png; do
    [ -f "$root$f" ] || die "$f is not there after the install"
done
missing_libs="$(in_root ldd /usr/bin/ringlab | grep 'not found' || true)"
[ -z "$missing_libs" ] || die "libraries missing for /usr/bin/ringlab: $missing_libs"
in_root ringlab --help > "$work/ringlab-help.txt" 2>&1 || die "ringlab --help failed (see $work/ringlab-help.txt)"
installed_kib="$(in_root dpkg-query -W -f='${Installed-Size}' ringlab)"
kib_after="$(sum_installed_kib)"
say "installed: ringlab's Installed-Size $installed_kib KiB; with its dependencies and Recommends $(( (kib_after - kib_before) / 1024 )) MiB ($n_with packages); without Recommends it would be $(( (kib_deps_min + installed_kib) / 1024 )) MiB ($n_without packages); apt install took $((t_inst1 - t_inst0)) s"

# --- the tools of the test (not needed by ringlab itself) ---------------------------------------
say "installing the test's tools: xvfb xauth x11-utils imagemagick"
in_root apt-get install -y --no-install-recommends xvfb xauth x11-utils imagemagick \
    >> "$work/install.log" 2>&1 || die "apt-get install xvfb xauth x11-utils imagemagick failed (see $work/install.log)"
in_root useradd --create-home --shell /bin/bash teacher >/dev/null 2>&1 || die "useradd teacher failed"

# --- Xvfb and the window ------------------------------------------------------------------------
# X servers share abstract sockets with the host (same network namespace): skip displays in use.
n="${RINGLAB_TEST_DISPLAY:-99}"
while grep -q "@/tmp/.X11-unix/X$n\$" /proc/net/unix 2>/dev/null || [ -e "/tmp/.X11-unix/X$n" ]; do
    n=$((n + 1))
done
say "starting Xvfb :$n (1920x1080x24) in the chroot"
chroot "$root" /usr/bin/env -i PATH=/usr/bin:/bin HOME=/root \
    Xvfb ":$n" -screen 0 1920x1080x24 -nolisten tcp > "$work/xvfb.log" 2>&1 &
pids+=("$!")
for _ in $(seq 1 50); do
    [ -e "$root/tmp/.X11-unix/X$n" ] && break
    sleep 0.2
done
[ -e "$root/tmp/.X11-unix/X$n" ] || die "Xvfb :$n did not start (see $work/xvfb.log)"

say "starting ringlab as the user teacher, DISPLAY=:$n, lavapipe; giving it $wait_s s"
t_run0=$(date +%s)
chroot --userspec=teacher:teacher "$root" /usr/bin/env -i PATH=/usr/bin:/bin HOME=/home/teacher \
    USER=teacher LANG=C.UTF-8 DISPLAY=":$n" XDG_RUNTIME_DIR=/tmp \
    VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \
    ringlab > "$work/ringlab.log" 2>&1 &
ringlab_pid=$!
pids+=("$ringlab_pid")
sleep "$wait_s"

running=yes
kill -0 "$ringlab_pid" 2>/dev/null || running=no
in_root env DISPLAY=":$n" xwininfo -root -tree > "$work/xwininfo.txt" 2>&1 || true
in_root env DISPLAY=":$n" import -window root /tmp/screenshot.png > "$work/import.log" 2>&1 \
    || die "import -window root failed (see $work/import.log)"
cp "$root/tmp/screenshot.png" "$work/screenshot.png"
colours="$(in_root identify -format '%k' /tmp/screenshot.png 2>/dev/null || echo 0)"
window_line="$(grep -i 'ringlab' "$work/xwininfo.txt" | head -n 1 || true)"
wm_class=""
window_id="$(printf '%s\n' "$window_line" | awk '{ print $1 }')"
if [ -n "$window_id" ]; then
    wm_class="$(in_root env DISPLAY=":$n" xprop -id "$window_id" WM_CLASS 2>/dev/null | sed 's/^WM_CLASS(STRING) = //' || true)"
fi
t_end=$(date +%s)

say "ringlab still running after $wait_s s: $running"
say "window: ${window_line:-none found}"
say "window's WM_CLASS: ${wm_class:-none} (the desktop entry's StartupWMClass is ringlab)"
say "screenshot: $work/screenshot.png, $colours colours"
say "times: clean root $((t_base - t0)) s (0 when cached), install $((t_inst1 - t_inst0)) s, whole test $((t_end - t0)) s (window run $((t_end - t_run0)) s)"

ok=yes
[ "$running" = yes ] || { ok=no; say "ringlab exited early; its output:"; cat "$work/ringlab.log" >&2; }
[ -n "$window_line" ] || { ok=no; say "no window named ringlab in xwininfo -root -tree ($work/xwininfo.txt)"; }
case "$wm_class" in
    *'"ringlab"'*) ;;
    *) ok=no; say "the window's WM_CLASS is not ringlab: the menu entry would not be matched to it" ;;
esac
[ "$colours" -gt 16 ] 2>/dev/null || { ok=no; say "the screenshot has only $colours colours: nothing was drawn"; }
if [ "$ok" = yes ]; then
    echo "PASS"
else
    echo "FAIL"
    exit 1
fi
