#!/usr/bin/env bash
# Writes the fuzzers' seed inputs (tests/fuzz/corpus/<target>/seed-*): small valid files of every
# form each reader takes, from data/ and the CLI. Run once from the repository root with the
# release build in place; the seeds are kept in the repository beside the inputs the fuzzers
# found (found-*), which the suite replays (FuzzCorpus.*).
set -euo pipefail
cd "$(dirname "$0")/../.."
OM=${OM:-build/release/offsetmap}
C=tests/fuzz/corpus
mkdir -p $C/height_map $C/gbuffer $C/engine_gbuffer $C/material_table $C/gltf
/usr/bin/python3 - "$C/height_map" <<'PY'
import sys
from PIL import Image
d = sys.argv[1]
Image.frombytes("L", (5, 3), bytes(range(0, 255, 17))).save(f"{d}/seed-grey8.png")
im = Image.new("I;16", (4, 4))
im.putdata([k * 4099 for k in range(16)])
im.save(f"{d}/seed-grey16.png")
Image.new("RGBA", (3, 2), (10, 200, 30, 128)).save(f"{d}/seed-rgba.png")
Image.frombytes("L", (3, 3), bytes([0, 64, 128, 192, 255, 1, 2, 3, 4])).save(f"{d}/seed-grey8.tif")
Image.frombytes("L", (4, 2), bytes(range(8))).save(f"{d}/seed-grey8.pgm")
PY
cp data/stairs.png $C/height_map/seed-stairs.png
$OM gbuffer --scene random --width 3 --height 2 -o $C/height_map/seed-float.exr >/dev/null
$OM gbuffer --scene random --width 6 --height 4 -o $C/gbuffer/seed-random.exr >/dev/null
$OM gbuffer --scene random --width 4 --height 4 --material-ids 1 2 \
    -o $C/gbuffer/seed-materials.exr >/dev/null
$OM gbuffer --engine-form gl --width 8 --height 4 -o $C/gbuffer/seed-engine-gl.exr >/dev/null
for form in gl zero-one reversed; do
    $OM gbuffer --engine-form $form --width 6 --height 4 \
        -o $C/engine_gbuffer/seed-engine-$form.exr >/dev/null
done
cp data/materials.json data/pillars.json data/room.json $C/material_table/
for f in $C/material_table/*.json; do mv "$f" "$(dirname "$f")/seed-$(basename "$f")"; done
cp data/pillars.gltf $C/gltf/seed-pillars.gltf
# The same scene as binary glTF: its data-URI buffer as the BIN chunk.
/usr/bin/python3 - data/pillars.gltf $C/gltf/seed-pillars.glb <<'PY'
import base64, json, struct, sys
g = json.load(open(sys.argv[1]))
uri = g["buffers"][0].pop("uri")
data = base64.b64decode(uri.split(",", 1)[1])
text = json.dumps(g, separators=(",", ":")).encode()
text += b" " * (-len(text) % 4)
data += b"\0" * (-len(data) % 4)
body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(data), 0x004E4942) + data
open(sys.argv[2], "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
PY
