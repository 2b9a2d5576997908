#!/bin/sh
# The tripod's test cut: frames 300..899 of the shared colours-tripod-30.mp4 (a pinhole 550 mm
# from the table, tilted 30 degrees) re-encoded small by libx264 (crf 24, yuv420p, 300
# frames/s), its truth's rows of those frames kept as they are (the film's own numbers, as the
# other -mid cuts keep them).
#
#   make-tripod.sh [SHARED]
set -eu
here=$(cd "$(dirname "$0")" && pwd)
shared=${1:-$here/../../../../shared/data/video}
ffmpeg -loglevel error -y -i "$shared/colours-tripod-30.mp4" \
    -vf "select='between(n,300,899)',setpts=N/300/TB" -r 300 \
    -c:v libx264 -crf 24 -pix_fmt yuv420p "$here/colours-tripod-30-mid.mp4"
awk -F, '/^#/ || /^frame/ { print; next } $1 >= 300 && $1 <= 899 { print }' \
    "$shared/colours-tripod-30.truth.csv" >"$here/colours-tripod-30-mid.truth.csv"
