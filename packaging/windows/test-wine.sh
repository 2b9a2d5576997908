#!/usr/bin/env bash
# ringlab.exe and ringlab-setup.exe tested under Wine (Debian's wine64), in a fresh prefix.
#
#   packaging/windows/build-windows.sh && cargo build --release && packaging/windows/test-wine.sh
#
# 1. simulate and fit under Wine, their JSON compared with the Linux binary's (test/compare.py);
# 2. the installer run silently: ringlab.exe, the uninstaller, the Start-menu entry and the
#    Add/Remove Programs key checked, then the uninstaller run silently and all of it gone;
# 3. the window opened under Xvfb (Wine's Vulkan on lavapipe), a screenshot after
#    WINDOW_WAIT seconds (30) per backend in WINDOW_BACKENDS ("default vulkan dx12");
# 4. `render --view 3d` tried.
# 1 and 2 decide the exit status; 3 and 4 are reported (target/windows/wine-test/summary.txt).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
wtarget="${CARGO_TARGET_DIR:-$root/target/windows}"
dist="$wtarget/dist"
work="$wtarget/wine-test"
linux_bin="${RINGLAB_LINUX_BIN:-$root/target/release/ringlab}"
window_wait="${WINDOW_WAIT:-30}"
window_backends="${WINDOW_BACKENDS:-default vulkan dx12}"
lvp_icd=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json

die() { echo "test-wine.sh: $*" >&2; exit 1; }
say() { echo "test-wine.sh: $*" >&2; }

sudo_prefix=""
if [ "$(id -u)" != 0 ]; then
    sudo_prefix=$(command -v sudo || true)
fi
apt_install() {
    command -v apt-get >/dev/null 2>&1 || die "missing: $* (Debian packages) and no apt-get to install them"
    say "installing Debian's $*"
    if ! { $sudo_prefix apt-get update -q &&
        $sudo_prefix env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@"; }; then
        die "could not install $*"
    fi
}
need() { command -v "$1" >/dev/null 2>&1 || apt_install "$2"; command -v "$1" >/dev/null 2>&1 || die "'$1' missing after installing '$2'"; }

[ -f "$dist/ringlab.exe" ] || die "$dist/ringlab.exe is missing: run packaging/windows/build-windows.sh first"
[ -f "$dist/ringlab-setup.exe" ] || die "$dist/ringlab-setup.exe is missing: run packaging/windows/build-windows.sh (without --exe-only)"
[ -x "$linux_bin" ] || die "$linux_bin is missing: run 'cargo build --release' (or set RINGLAB_LINUX_BIN)"
need python3 python3
need x86_64-w64-mingw32-gcc gcc-mingw-w64-x86-64
need Xvfb xvfb
need xwd x11-apps
# Debian puts the 64-bit loader in /usr/lib/wine; `wine64` is on PATH elsewhere.
wine64=$(command -v wine64 || true)
if [ -z "$wine64" ]; then
    [ -x /usr/lib/wine/wine64 ] || apt_install wine64 wine
    wine64=$(command -v wine64 || echo /usr/lib/wine/wine64)
fi
[ -x "$wine64" ] || die "no wine64 found (Debian's package wine64)"
wineserver=$(command -v wineserver || echo /usr/lib/wine/wineserver64)
[ -x "$wineserver" ] || die "no wineserver found (Debian's package wine64)"
dpkg -s libvulkan1 mesa-vulkan-drivers >/dev/null 2>&1 || apt_install libvulkan1 mesa-vulkan-drivers

rm -rf "$work"
mkdir -p "$work/run" "$work/no-standin"
summary="$work/summary.txt"
: >"$summary"
note() { echo "$*" | tee -a "$summary" >&2; }

export WINEPREFIX="$work/prefix" WINEARCH=win64 WINEDEBUG="${WINEDEBUG:-fixme-all}"
# No Mono or Gecko download prompts, no menu entries written into the host's desktop.
export WINEDLLOVERRIDES="mscoree,mshtml=;winemenubuilder.exe=d"
unset DISPLAY
say "fresh prefix $WINEPREFIX ($("$wine64" --version))"
"$wine64" wineboot --init >"$work/wineboot.log" 2>&1 || die "wineboot failed, see $work/wineboot.log"
"$wineserver" -w

# The test folder: ringlab.exe and the ProcessPrng stand-in Wine 8 lacks.
cp "$dist/ringlab.exe" "$work/run/"
x86_64-w64-mingw32-gcc -O2 -shared -o "$work/run/bcryptprimitives.dll" \
    "$here/test/bcryptprimitives.c" -ladvapi32
cp "$dist/ringlab.exe" "$work/no-standin/"

status=0
cd "$root"

# Without the stand-in, for the record.
set +e
"$wine64" "$work/no-standin/ringlab.exe" --version >"$work/no-standin.out" 2>"$work/no-standin.err"
rc=$?
set -e
note "without bcryptprimitives.dll: exit $rc; $(grep -m1 'import_dll' "$work/no-standin.err" || echo 'no import error')"
note "ringlab.exe --version under Wine: $("$wine64" "$work/run/ringlab.exe" --version 2>/dev/null | tr -d '\r')"

# 1. The numbers.
compare() { # NAME KIND ARGS...
    local name=$1 kind=$2
    shift 2
    local t0 t1 t2
    t0=$(date +%s%N)
    "$linux_bin" "$@" >"$work/$name.linux.json" 2>"$work/$name.linux.err" || die "Linux '$*' failed: $work/$name.linux.err"
    t1=$(date +%s%N)
    "$wine64" "$work/run/ringlab.exe" "$@" >"$work/$name.wine.json" 2>"$work/$name.wine.err" ||
        { note "FAIL: under Wine '$*' failed: $(tail -3 "$work/$name.wine.err")"; status=1; return; }
    t2=$(date +%s%N)
    note "$name: Linux $(((t1 - t0) / 1000000)) ms, Wine $(((t2 - t1) / 1000000)) ms (wall, Wine's start included)"
    if python3 "$here/test/compare.py" "$kind" "$work/$name.linux.json" "$work/$name.wine.json" \
        --markdown "$work/$name.table.md" >"$work/$name.compare.txt"; then
        note "$name: $(head -n 1 "$work/$name.compare.txt")"
    else
        note "FAIL $name: $(head -n 1 "$work/$name.compare.txt") (table: $work/$name.table.md)"
        status=1
    fi
}
compare simulate simulate simulate --preset paper-ring --json
compare fit fit fit tests/data/sample-ring.csv --json

# 2. The installer.
pf="$WINEPREFIX/drive_c/Program Files/ringlab"
lnk="$WINEPREFIX/drive_c/ProgramData/Microsoft/Windows/Start Menu/Programs/ringlab.lnk"
key='HKLM\Software\Microsoft\Windows\CurrentVersion\Uninstall\ringlab'
check() { # DESCRIPTION TEST...
    local what=$1
    shift
    if "$@"; then note "ok: $what"; else note "FAIL: $what"; status=1; fi
}
"$wine64" "$dist/ringlab-setup.exe" /S >"$work/install.log" 2>&1 || { note "FAIL: ringlab-setup.exe /S exited $?"; status=1; }
"$wineserver" -w
check "installed $pf/ringlab.exe, the same bytes as dist/ringlab.exe" cmp -s "$pf/ringlab.exe" "$dist/ringlab.exe"
check "installed $pf/uninstall.exe" test -f "$pf/uninstall.exe"
check "Start-menu entry $lnk" test -f "$lnk"
check "no desktop shortcut in a silent install (it is unticked)" test ! -e "$WINEPREFIX/drive_c/users/Public/Desktop/ringlab.lnk"
"$wine64" reg query "$key" >"$work/uninstall-key.txt" 2>&1 || true
check "Add/Remove Programs key with DisplayVersion $(tr -d '\r' <"$work/uninstall-key.txt" | awk '/DisplayVersion/ {print $3}')" \
    grep -q UninstallString "$work/uninstall-key.txt"
"$wine64" "$pf/uninstall.exe" /S >"$work/uninstall.log" 2>&1 || { note "FAIL: uninstall.exe /S exited $?"; status=1; }
"$wineserver" -w
# NSIS's uninstaller runs from a copy in %TEMP%: wait for it to finish removing.
for _ in $(seq 30); do [ -e "$pf" ] || break; sleep 1; done
check "uninstalled: $pf gone" test ! -e "$pf"
check "uninstalled: Start-menu entry gone" test ! -e "$lnk"
if "$wine64" reg query "$key" >"$work/uninstall-key-after.txt" 2>&1; then
    note "FAIL: the Uninstall key is still there"
    status=1
else
    note "ok: the Uninstall key is gone"
fi

# 3. The window, under Xvfb.
display_n=$((90 + RANDOM % 9))
Xvfb ":$display_n" -screen 0 1600x1000x24 -nolisten tcp >"$work/xvfb.log" 2>&1 &
xvfb_pid=$!
trap 'kill "$xvfb_pid" 2>/dev/null || true; "$wineserver" -k 2>/dev/null || true' EXIT
sleep 2
kill -0 "$xvfb_pid" 2>/dev/null || die "Xvfb did not start: $(cat "$work/xvfb.log")"
export DISPLAY=":$display_n"
[ -f "$lvp_icd" ] && export VK_DRIVER_FILES="$lvp_icd"
for backend in $window_backends; do
    log="$work/window-$backend.log"
    if [ "$backend" = default ]; then
        "$wine64" "$work/run/ringlab.exe" >"$log" 2>&1 &
    else
        WGPU_BACKEND="$backend" "$wine64" "$work/run/ringlab.exe" >"$log" 2>&1 &
    fi
    app_pid=$!
    sleep "$window_wait"
    if kill -0 "$app_pid" 2>/dev/null; then alive="still running"; else
        wait "$app_pid" && rc=0 || rc=$?
        alive="exited with $rc"
    fi
    if xwd -root -silent >"$work/window-$backend.xwd" &&
        seen=$(python3 "$here/test/xwd2png.py" "$work/window-$backend.xwd" "$work/window-$backend.png" 2>&1); then
        rm -f "$work/window-$backend.xwd"
    else
        seen="no screenshot: ${seen:-xwd failed}"
    fi
    note "window ($backend) after ${window_wait} s: $alive; screenshot $work/window-$backend.png: $seen"
    grep -v '^$' "$log" | tail -n 4 | sed 's/^/    /' | tee -a "$summary" >&2 || true
    kill "$app_pid" 2>/dev/null || true
    "$wineserver" -k 2>/dev/null || true
    "$wineserver" -w 2>/dev/null || true
done

# 4. A picture without a window (Vulkan only, as on Linux).
set +e
t0=$(date +%s)
timeout 300 "$wine64" "$work/run/ringlab.exe" render --preset paper-ring --time 60 --view 3d \
    --out "$work/r.png" >"$work/render.log" 2>&1
rc=$?
set -e
if [ "$rc" = 0 ] && [ -s "$work/r.png" ]; then
    note "render: $work/r.png in $(($(date +%s) - t0)) s ($(file -b "$work/r.png" 2>/dev/null || stat -c '%s bytes' "$work/r.png"))"
else
    note "render: exit $rc after $(($(date +%s) - t0)) s: $(grep -v '^$' "$work/render.log" | tail -n 2 | tr '\n' ' ')"
fi

note "result: $([ "$status" = 0 ] && echo 'the numbers and the installer pass' || echo FAILED)"
exit "$status"
