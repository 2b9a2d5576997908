#!/bin/sh
# A film shaken as a hand holds a camera: each frame n turned by a(n) about the picture's centre
# and shifted by (dx(n), dy(n)), slow and smooth (up to about 20 px and 2 degrees), then cut to
# the picture less a 56 px border (in RGB, so that the crop moves by whole pixels, not pairs) (what a turned frame leaves black at its corners stays out),
# re-encoded by libx264 (crf 23, yuv420p). Its truth is the film's truth moved the same way: in
# the first frame's camera (NAME-shaken.truth.csv, the table's frame, as a tracker writes a
# hand-held film) and where the marks are in each frame as filmed (NAME-shaken.truth.image.csv).
#
#   make-shaken.sh FILM.mp4 TRUTH.csv OUT_DIR [FPS]
set -eu
film=$1; truth=$2; out=$3; fps=${4:-300}
name=$(basename "$film" .mp4)
mkdir -p "$out"
size=$(ffprobe -v error -select_streams v:0 -show_entries stream=width,height -of csv=p=0 "$film")
w=${size%,*}; h=${size#*,}
# The path, in seconds t = n / fps: a(t) in radians (clockwise on the screen, as ffmpeg's rotate
# turns), the shift in px.
a="0.030*sin(2*PI*0.9*T)+0.008*sin(2*PI*2.3*T+1)"
dx="14*sin(2*PI*0.7*T+0.5)+5*sin(2*PI*1.9*T)"
dy="12*sin(2*PI*0.8*T+2)+4*sin(2*PI*2.1*T+0.3)"
b=56
ff() { echo "$1" | sed "s/T/(n\/$fps)/g"; }
ffmpeg -loglevel error -y -i "$film" -vf \
  "format=rgb24,rotate='$(ff "$a")':c=black,crop=w=$((w - 2 * b)):h=$((h - 2 * b)):x='$b-($(ff "$dx"))':y='$b-($(ff "$dy"))':exact=1,format=yuv420p" \
  -c:v libx264 -crf 23 -pix_fmt yuv420p -r "$fps" "$out/$name-shaken.mp4"
# The truth moved: p' = c + R(a) (p - c) - (x, y), c the full picture's centre and (x, y) the
# crop's corner, b - (dx, dy) rounded to whole pixels as ffmpeg's crop takes it.
move() {
  awk -F, -v OFS=, -v fps="$fps" -v w="$w" -v h="$h" -v b="$b" -v first="$1" '
    function mv(x, y, T,   A, DX, DY, c, s, u, v) {
      PI = 3.141592653589793
      A = 0.030*sin(2*PI*0.9*T)+0.008*sin(2*PI*2.3*T+1)
      DX = 14*sin(2*PI*0.7*T+0.5)+5*sin(2*PI*1.9*T)
      DY = 12*sin(2*PI*0.8*T+2)+4*sin(2*PI*2.1*T+0.3)
      c = cos(A); s = sin(A); u = x - w / 2; v = y - h / 2
      X = w / 2 + c * u - s * v - int(b - DX + 0.5); Y = h / 2 + s * u + c * v - int(b - DY + 0.5)
    }
    /^#/ { if ($0 ~ /image_width_px/) { print "# image_width_px = " w - 2 * b; next }
           if ($0 ~ /image_height_px/) { print "# image_height_px = " h - 2 * b; next }
           print; next }
    /^frame/ { print; next }
    n0 == "" { n0 = $1 }
    {
      T = first ? 0 : ($1 - n0) / fps
      for (k = 0; k < 4; k++) {
        i = 2 + 2 * k
        if ($i != "" && $(i + 1) != "") { mv($i, $(i + 1), T); $i = sprintf("%.3f", X); $(i + 1) = sprintf("%.3f", Y) }
      }
      print
    }' "$truth"
}
move 1 >"$out/$name-shaken.truth.csv"
move 0 >"$out/$name-shaken.truth.image.csv"
