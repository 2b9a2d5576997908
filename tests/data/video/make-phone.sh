#!/bin/sh
# Stand-ins for a phone's film: the shared films (../../../../shared/data/video/) scaled down to
# 2 px per mm (area-averaged), re-encoded at 240 frames/s by libx264 at a given crf (yuv420p),
# the true centres scaled alike.
#
#   make-phone.sh OUTDIR [SHARED]     every stand-in of docs/film.md, at crf 23 and 28, in OUTDIR
#   make-phone.sh --test-cut [SHARED] the small cuts the tests keep (tests/data/video/)
#
# COVER (optional, "A B"): frames A..B of the cut covered whole in grey (a hand before the
# lens), the truth's marks hidden there. DROP5=1: every fifth frame of the 300 frames/s film
# left out, so that the ring moves as far between frames as a film truly taken at 240.
# A pixel's centre is at integer coordinates in the truth as in the tracker, so a centre
# scaled by s is (x + 0.5) s - 0.5, as the scale filter maps pixels.
set -eu
here=$(cd "$(dirname "$0")" && pwd)

# stand_in SHARED NAME FIRST LAST CRF OUT [COVER]: frames FIRST..LAST of NAME as OUT.mp4,
# OUT.truth.csv
stand_in() {
    cover_from=$(echo "${7:-}" | awk '{print ($1 == "" ? -1 : $1)}')
    cover_to=$(echo "${7:-}" | awk '{print ($2 == "" ? -1 : $2)}')
    cover=""
    if [ "$cover_from" -ge 0 ]; then
        cover=",drawbox=x=0:y=0:w=iw:h=ih:color=0x7f7f7f:t=fill:enable='between(n,$cover_from,$cover_to)'"
    fi
    keep=""
    if [ -n "${DROP5:-}" ]; then
        keep="*not(eq(mod(n\\,5)\\,4))"
    fi
    src="$1/$2.mp4"
    truth="$1/$2.truth.csv"
    scale=$(awk -F'= *' '/^# px_per_mm/ {print $2}' "$truth")
    w=$(awk -F'= *' '/^# image_width_px/ {print $2}' "$truth")
    h=$(awk -F'= *' '/^# image_height_px/ {print $2}' "$truth")
    # Even sizes (4:2:0) nearest 2 px per mm.
    nw=$(awk -v w="$w" -v s="$scale" 'BEGIN {printf "%d", int(w * 2 / s / 2 + 0.5) * 2}')
    nh=$(awk -v h="$h" -v s="$scale" 'BEGIN {printf "%d", int(h * 2 / s / 2 + 0.5) * 2}')
    ffmpeg -loglevel error -y -i "$src" \
        -vf "select='between(n,$3,$4)$keep',scale=$nw:$nh:flags=area,setpts=N/240/TB$cover" \
        -r 240 -c:v libx264 -crf "$5" -pix_fmt yuv420p "$6.mp4"
    awk -F, -v OFS=, -v first="$3" -v last="$4" -v drop5="${DROP5:-}" \
        -v w="$w" -v h="$h" -v nw="$nw" -v nh="$nh" -v ca="$cover_from" -v cb="$cover_to" '
        BEGIN { fx = nw / w; fy = nh / h; k = 0 }
        /^# px_per_mm/ { split($0, a, "= *"); printf "# px_per_mm = %.6f\n", a[2] * (fx + fy) / 2; next }
        /^# fps/ { print "# fps = 240"; next }
        /^# image_width_px/ { print "# image_width_px = " nw; next }
        /^# image_height_px/ { print "# image_height_px = " nh; next }
        /^#/ || /^frame/ { print; next }
        $1 >= first && $1 <= last && !(drop5 != "" && $1 % 5 == 4) {
            $1 = drop5 != "" ? k++ : $1 - first
            for (i = 2; i <= 9; i++) if ($1 >= ca && $1 <= cb) $i = ""; else if ($i != "") {
                $i = sprintf("%.2f", ($i + 0.5) * (i % 2 == 0 ? fx : fy) - 0.5)
            }
            print
        }' "$truth" >"$6.truth.csv"
}

if [ "${1:-}" = "--test-cut" ]; then
    shared=${2:-$here/../../../../shared/data/video}
    stand_in "$shared" colours-none 300 539 28 "$here/colours-none-phone"
    stand_in "$shared" disk-dark-none 0 535 28 "$here/disk-dark-none-phone"
    stand_in "$shared" colours-none 249 848 28 "$here/colours-none-phone-long"
    stand_in "$shared" dark-perspective 249 848 28 "$here/dark-perspective-phone"
    stand_in "$shared" colours-reynolds-flicker 249 848 28 "$here/colours-reynolds-flicker-phone-long"
    stand_in "$shared" colours-none 0 1812 28 "$here/colours-none-phone-whole"
    stand_in "$shared" dark-perspective 249 848 28 "$here/dark-perspective-phone-covered" "300 359"
    # A phone held upright: the same frames, stored on their side with a rotation to show
    # them by (ffmpeg 5's tag; a later ffmpeg takes -display_rotation 90 before -i).
    ffmpeg -loglevel error -y -i "$here/colours-none-phone.mp4" -c copy \
        -metadata:s:v:0 rotate=90 "$here/colours-none-phone-upright.mp4"
    # A film whose rate varies: frames 100-119 of the disk's cut never taken.
    ffmpeg -loglevel error -y -i "$here/disk-dark-none-phone.mp4" \
        -vf "select='not(between(n,100,119))'" -vsync vfr -c:v libx264 -crf 18 \
        "$here/disk-dark-none-phone-vfr.mp4"
    exit 0
fi

out=${1:?usage: make-phone.sh OUTDIR [SHARED] | --test-cut [SHARED]}
shared=${2:-$here/../../../../shared/data/video}
mkdir -p "$out"
for crf in 23 28; do
    stand_in "$shared" colours-none 249 848 "$crf" "$out/colours-none-crf$crf"
    stand_in "$shared" colours-none 0 299 "$crf" "$out/colours-none-opening-crf$crf"
    stand_in "$shared" colours-reynolds-flicker 249 848 "$crf" "$out/colours-reynolds-flicker-crf$crf"
    stand_in "$shared" dark-perspective 249 848 "$crf" "$out/dark-perspective-crf$crf"
    stand_in "$shared" disk-dark-none 0 535 "$crf" "$out/disk-dark-none-crf$crf"
    for name in colours-none colours-reynolds-flicker dark-perspective; do
        last=$(awk -F, '/^[0-9]/ {n = $1} END {print n}' "$shared/$name.truth.csv")
        stand_in "$shared" "$name" 0 "$last" "$crf" "$out/$name-whole-crf$crf"
    done
done
for name in colours-none colours-reynolds-flicker dark-perspective; do
    last=$(awk -F, '/^[0-9]/ {n = $1} END {print n}' "$shared/$name.truth.csv")
    DROP5=1 stand_in "$shared" "$name" 0 "$last" 28 "$out/$name-whole-240-crf28"
done
