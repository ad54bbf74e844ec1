#!/usr/bin/env bash
# Pixel-for-pixel snapshot of what the CLI computes: every method on five scenarios (wrap and
# clamp, r < 1, each grazing policy, both LOD modes, hard and soft shadows), each output's uv',
# depth, fetches and flags (EXR) and shaded image (PNG) hashed into one manifest. For refactors
# that must not change a pixel:
#   tests/snapshot.sh build/release/offsetmap > before.txt   (on the old build)
#   tests/snapshot.sh build/release/offsetmap > after.txt; diff before.txt after.txt
set -euo pipefail
om=${1:-build/release/offsetmap}
data=$(cd "$(dirname "$0")/../data" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scenarios=(
    "plane-wrap|--height-map $data/rocks.png --scene plane --width 320 --height 180 --shadows soft"
    "random-clamp-cap|--height-map $data/rocks.png --scene random --width 128 --height 96 --scale 0.1 --reference-plane 0.6 --address clamp --grazing cap --max-offset 16 --shadows hard --light 0.9 0.2 0.3"
    "plane-lod|--height-map $data/rocks.png --scene plane --width 320 --height 180 --lod-threshold 3 --shadows soft"
    "plane-footprint-limit|--height-map $data/stairs.png --scene plane --width 320 --height 180 --lod-footprint --grazing limit --tile-mask --address clamp --shadows soft --light 0.8 0.3 0.4"
    "sweep-grazing|--height-map $data/noise.png --scene sweep --elev-min 0.5 --grazing-min-deg 0.5 --scale 0.08"
)
methods=$("$om" methods --json | /usr/bin/python3 -c 'import json,sys; print(" ".join(m["name"] for m in json.load(sys.stdin)))')
for entry in "${scenarios[@]}"; do
    name=${entry%%|*} args=${entry#*|}
    for m in $methods; do
        # shellcheck disable=SC2086
        "$om" render $args --method "$m" --uv-out "$tmp/o.exr" --color-out "$tmp/o.png" >/dev/null
        # The EXR header carries its write time (capDate): hashed with the date blanked.
        exr=$(/usr/bin/python3 -c 'import hashlib, re, sys
print(hashlib.md5(re.sub(rb"\d{4}:\d\d:\d\d \d\d:\d\d:\d\d", b"", open(sys.argv[1], "rb").read())).hexdigest()[:12])' "$tmp/o.exr")
        echo "$name $m $exr $(md5sum <"$tmp/o.png" | cut -c1-12)"
    done
done
