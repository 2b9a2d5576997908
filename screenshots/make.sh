#!/usr/bin/env bash
# Regenerates the pictures of the README and docs/ with `ringlab render` (no window; any Vulkan adapter, e.g.
# lavapipe). Run from anywhere: bash screenshots/make.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release
r=target/release/ringlab
out=screenshots
# The paper's ring a fifth of the way in: prograde cycloids, the camera following it.
$r render --preset paper-ring --time 20 --out $out/ring-mid-run.png
# The retrograde turn: the whole path so far from a fixed camera.
$r render --preset paper-ring --time 80 --camera=-1.7,1.0,17 --out $out/retrograde-turn.png
# Ring and disk-like drag side by side on one clock, and their paths from above.
$r render --preset paper-ring --compare paper-disk-drag --time 40 --camera=-1.7,0.95,14 --out $out/ring-vs-disk.png
$r render --preset paper-ring --compare paper-disk-drag --time 126 --view top --width 1100 --height 520 --out $out/ring-vs-disk-top.png
# The whole window at t = 60, with the "why" note open.
$r render --preset paper-ring --time 60 --view app --width 1480 --height 920 --why --out $out/app.png
# The sample recording opened and fitted: data (green) and the fitted model replayed together.
$r render --view app --width 1480 --height 920 --recording ../shared/data/sample-ring.csv --fit --time 60 --out $out/app-recording-fit.png
# A recording with slip concealed (synth's own, 0.5 px of noise), diagnosed in the window: the
# Diagnose tab, the mismatch shaded, the improved model (with slip) replayed beside the data.
tmp=$(mktemp -d)
$r synth --preset steel-ring --effect slip --effect-strength 0.3 --noise-px 0.5 --seed 3 --out $tmp/slip.csv
$r render --view app --width 1480 --height 920 --recording $tmp/slip.csv --diagnose --time 40 --out $out/app-diagnosed.png
rm -rf "$tmp"
