#!/usr/bin/env bash
# Pixel-for-pixel snapshot of the rendered frame (`offsetmap frame`), as tests/snapshot.sh is of the
# pass: every picture and plane a few small frames write (the room deferred and forward, curved
# with the layer behind, under the sun's displaced shadow map, the pillars curved under the sun
# with the truth, the triplanar terrain), each file hashed into one manifest. For refactors of the
# frame that must not change a pixel:
#   tests/frame_snapshot.sh build/release/offsetmap > before.txt   (on the old build)
#   tests/frame_snapshot.sh build/release/offsetmap > after.txt; diff before.txt after.txt
set -euo pipefail
om=${1:-build/release/offsetmap}
data=$(cd "$(dirname "$0")/../data" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
size="--width 200 --height 112 --repeats 1"
scenarios=(
    "room-forward|--forward --shadows soft"
    "room-curved-behind|--curvature --layers 2 --shadows hard"
    "room-sun|--sun 40,60 --shadow-size 256 --shadows map+soft"
    "pillars-sun-truth|--scene $data/pillars.gltf --sun 20,60 --shadow-size 256 --curvature --layers 2 --truth --truth-level 1 --shadows map"
    "terrain|--scene $data/terrain.gltf --shadows soft"
)
for entry in "${scenarios[@]}"; do
    name=${entry%%|*} args=${entry#*|}
    # shellcheck disable=SC2086
    "$om" frame $size $args -o "$tmp/$name" >/dev/null
    # The EXR header carries its write time (capDate): hashed with the date blanked; frame.json
    # and the truth's chart of error against cost (truth-pareto.png) carry times, and are left
    # out.
    (cd "$tmp/$name" && find . -type f \( -name '*.png' -o -name '*.exr' \) \
        ! -name truth-pareto.png | LC_ALL=C sort) |
        while read -r f; do
            echo "$name ${f#./} $(/usr/bin/python3 -c 'import hashlib, re, sys
print(hashlib.md5(re.sub(rb"\d{4}:\d\d:\d\d \d\d:\d\d:\d\d", b"", open(sys.argv[1], "rb").read())).hexdigest()[:12])' "$tmp/$name/$f")"
        done
done
