#!/usr/bin/env bash
# Regenerates every measurement the pages (README.md, docs/*.md) cite: data files into docs/data/,
# charts into docs/img/ (about 20 minutes on 2 cores; run it on a quiet machine, timings are in the
# data). Then `/usr/bin/python3 tests/readme_figures.py --write` rewrites the pages' marked figures
# and generated tables from these files, and `./run test` checks that they agree.
#   docs/regenerate.sh [demo|sweep|failure|temporal|bench|materials|frame|truth|rebuild ...]
#   (default: all)
set -euo pipefail
cd "$(dirname "$0")/.."
./run build >/dev/null
OM=./build/release/offsetmap
DATA=docs/data IMG=docs/img
mkdir -p "$DATA" "$IMG"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=(demo sweep failure temporal bench materials frame truth rebuild)
for part in "${parts[@]}"; do
    case $part in
    demo)  # the README's first table: every method on the demo scene
        $OM compare --height-map data/rocks.png --width 640 --height 360 --shadows soft -o "$tmp/demo"
        cp "$tmp/demo/summary.json" "$DATA/demo-summary.json"
        ;;
    sweep)  # the full sweep: seven maps x camera and random views, every method's grid
        $OM sweep --data data -o "$tmp/sweep"
        cp "$tmp/sweep/sweep.csv" "$DATA/sweep.csv"
        for f in pareto-ns pareto-fetches pareto-by-map pareto-cheap; do cp "$tmp/sweep/$f.png" "$IMG/"; done
        ;;
    failure)  # failure maps: the bricks under each grazing policy, and smooth bumps
        for policy in clamp limit cap; do
            $OM failure-map --height-map data/rocks.png --grazing $policy -o "$tmp/f-$policy"
            cp "$tmp/f-$policy/failure.csv" "$DATA/failure-rocks-$policy.csv"
        done
        cp "$tmp/f-clamp/failure-map.png" "$IMG/failure-map-rocks.png"
        cp "$tmp/f-limit/failure-map.png" "$IMG/failure-map-rocks-limit.png"
        cp "$tmp/f-cap/failure-map.png" "$IMG/failure-map-rocks-cap.png"
        $OM failure-map --height-map data/bumps.png -o "$tmp/f-bumps"
        cp "$tmp/f-bumps/failure.csv" "$DATA/failure-bumps.csv"
        cp "$tmp/f-bumps/failure-map.png" "$IMG/failure-map-bumps.png"
        ;;
    temporal)  # stability along a camera path over the bricks
        $OM temporal --height-map data/rocks.png -o "$tmp/temporal"
        cp "$tmp/temporal/temporal.csv" "$DATA/temporal.csv"
        cp "$tmp/temporal/temporal.png" "$IMG/"
        ;;
    bench)  # throughput: two full runs; the README cites the second (ratios moved between them)
        ./build/release/offsetmap_bench --out "$tmp/bench1" >/dev/null
        ./build/release/offsetmap_bench --out "$tmp/bench2"
        cp "$tmp/bench1/bench.json" "$DATA/bench-run1.json"
        cp "$tmp/bench2/bench.json" "$DATA/bench.json"
        cp "$tmp/bench2/bench-growth.png" "$IMG/"
        ;;
    materials)  # the demo's frame of four materials, and the material frame's bench part
        $OM render --materials data/materials.json --width 640 --height 360 --camera-height 0.9 \
            --pitch 28 --shadows soft --explain --report "$tmp/materials"
        cp "$tmp/materials/materials.json" "$DATA/materials-demo.json"
        cp "$tmp/materials/materials-sheet.png" "$IMG/materials-sheet.png"
        ./build/release/offsetmap_bench --materials --out "$tmp/bench-materials"
        cp "$tmp/bench-materials/bench-materials.json" "$DATA/bench-materials.json"
        ;;
    frame)  # the rendered room: 1080p pass times, the frame sheet, the box's silhouettes with and
        # without the tile mask, the glTF scene, the failure map over the room's views, and the
        # kernels against the GLSL peer
        $OM frame --forward --repeats 5 -o "$tmp/frame1080"
        cp "$tmp/frame1080/frame.json" "$DATA/frame-1080p.json"
        # The same under PoCL's AVX2 target, and each pass against the offset pass on both
        # (offsetmap_bench --frame: every shadow mode, in turns).
        POCL_KERNELLIB_NAME=avx2 POCL_LLVM_CPU_NAME=znver3 \
            $OM frame --repeats 5 -o "$tmp/frame1080-avx2"
        cp "$tmp/frame1080-avx2/frame.json" "$DATA/frame-1080p-avx2.json"
        ./build/release/offsetmap_bench --frame --target-ms 450 --out "$tmp/bench-frame"
        cp "$tmp/bench-frame/bench-frame.json" "$DATA/bench-frame.json"
        POCL_KERNELLIB_NAME=avx2 POCL_LLVM_CPU_NAME=znver3 \
            ./build/release/offsetmap_bench --frame --target-ms 450 --out "$tmp/bench-frame-avx2"
        cp "$tmp/bench-frame-avx2/bench-frame.json" "$DATA/bench-frame-avx2.json"
        # the curved scene's frame: the tangent plane, the curved trace, the layer behind
        ./build/release/offsetmap_bench --curved --out "$tmp/bench-curved"
        cp "$tmp/bench-curved/bench-curved.json" "$DATA/bench-curved.json"
        ./build/release/offsetmap_bench --triplanar --target-ms 600 --out "$tmp/bench-triplanar"
        cp "$tmp/bench-triplanar/bench-triplanar.json" "$DATA/bench-triplanar.json"
        # The terrain (no uv, triplanar): the frame and the projections each pixel traced.
        $OM frame --scene data/terrain.gltf --width 640 --height 360 --shadows soft --repeats 1 \
            --camera=-2.6,1.7,3.6,0.3,0.5,-0.4 -o "$tmp/terrain"
        cp "$tmp/terrain/frame.json" "$DATA/frame-terrain.json"
        /usr/bin/python3 docs/crop_figure.py "$IMG/frame-terrain.png" 0 100 640 330 1 \
            "$tmp/terrain/final.png" "triplanar, no uv (pom, soft self-shadows)" \
            "$tmp/terrain/triplanar.png" "projections traced: one, two, three"
        $OM frame --forward --shadows soft --width 640 --height 360 -o "$tmp/frame"
        cp "$tmp/frame/frame-sheet.png" "$IMG/frame-sheet.png"
        # The box in bricks (its faces are one uv square each, as the mask needs), close up.
        for mask in false true; do
            sed -e 's#"height_map": "#"height_map": "'"$PWD"'/data/#' \
                -e 's#stairs.png", "scale": 0.06,#rocks.png", "scale": 0.08, "tile_mask": '$mask',#' \
                -e 's#"method": "relief", "params": {"linear": 16, "binary": 6}#"method": "pom", "params": {"min_samples": 8, "max_samples": 32}#' \
                data/room.json >"$tmp/box-$mask.json"
            $OM frame --materials "$tmp/box-$mask.json" --camera=-0.2,1.3,0.6,-1.3,0.5,-1.9,50 \
                --width 960 --height 540 --forward --repeats 1 --shadows hard -o "$tmp/box-$mask"
        done
        /usr/bin/python3 docs/crop_figure.py "$IMG/frame-silhouettes.png" 318 150 478 300 2 \
            "$tmp/box-false/final.png" "deferred, no tile mask" \
            "$tmp/box-true/final.png" "deferred, tile mask" \
            "$tmp/box-true/final-forward.png" "forward, tile mask (discard)"
        # The sun's displaced shadow map and the frame's points tested against it.
        $OM frame --width 640 --height 360 --sun 40,60 --shadow-size 2048 --repeats 1 -o "$tmp/sun"
        cp "$tmp/sun/shadow-mask.png" "$IMG/frame-sun-mask.png"
        # The pillars shaded with the sun's displaced map, and their shadows against the truth's.
        $OM frame --scene data/pillars.gltf --width 640 --height 360 --sun 20,60 --curvature \
            --shadows map+soft --shadow-size 2048 --repeats 1 -o "$tmp/sun-pillars"
        cp "$tmp/sun-pillars/final.png" "$IMG/frame-sun-shadows.png"
        $OM frame --scene data/pillars.gltf --width 480 --height 270 --sun 20,60 --curvature \
            --shadows map --shadow-size 1024 --truth --repeats 1 -o "$tmp/sun-truth"
        /usr/bin/python3 docs/crop_figure.py "$IMG/frame-sun-truth.png" 100 40 400 220 1.5 \
            "$tmp/sun-truth/shadow-truth-flat.png" "flat map" \
            "$tmp/sun-truth/shadow-truth-displaced.png" "displaced map"
        $OM frame --scene data/pillars.gltf --width 640 --height 360 --shadows soft -o "$tmp/pillars"
        cp "$tmp/pillars/final.png" "$IMG/frame-pillars.png"
        $OM frame --width 640 --height 360 --repeats 1 -o "$tmp/room"
        $OM failure-map --height-map data/rocks.png --gbuffer "$tmp/room/gbuffer.exr" -o "$tmp/f-room"
        cp "$tmp/f-room/failure.csv" "$DATA/failure-rocks-room.csv"
        cp "$tmp/f-room/failure-map.png" "$IMG/failure-map-rocks-room.png"
        ./build/release/offsetmap_bench --glsl-peer --out "$tmp/peer"
        cp "$tmp/peer/bench-glsl-peer.json" "$DATA/bench-glsl-peer.json"
        cp "$tmp/peer/bench-glsl-peer.png" "$IMG/"
        ;;
    truth)  # the room, data/pillars.gltf and data/curved.gltf against the displaced mesh, each
        # frame variant (docs/renderer.md): about a minute and 3.2 GB each; then the terrain
        for scene in room pillars curved; do
            file=$scene
            [ $scene = room ] || file=data/$scene.gltf
            $OM frame --scene $file --width 960 --height 540 --truth --forward --curvature \
                --layers 2 -o "$tmp/truth-$scene"
            cp "$tmp/truth-$scene/frame.json" "$DATA/truth-$scene.json"
            cp "$tmp/truth-$scene/truth-sheet.png" "$IMG/truth-$scene.png"
            cp "$tmp/truth-$scene/truth-pareto.png" "$IMG/truth-pareto-$scene.png"
        done
        # the sphere's and the torus's outlines: one layer over the tangent plane, over the curved
        # base, and with the layer behind
        for crop in "sphere 180 170 360 350" "torus 540 170 720 350"; do
            set -- $crop
            /usr/bin/python3 docs/crop_figure.py "$IMG/curved-edges-$1.png" $2 $3 $4 $5 2 \
                "$tmp/truth-curved/coverage-deferred.png" "deferred (tangent plane)" \
                "$tmp/truth-curved/coverage-deferred-curved.png" "over the curved base" \
                "$tmp/truth-curved/coverage-deferred-two-layers.png" "and the layer behind"
        done
        # the terrain (triplanar, docs/renderer.md): its frame against its truth with pom and
        # exact, and with the kernels tracing each projection's ray over its axis plane (the
        # shear dropped, as the mutant triplanar-ray-over-axis drops it): what the ray over the
        # surface changed
        terrain=(--scene data/terrain.gltf --width 640 --height 360 --truth
                 --camera=-2.6,1.7,3.6,0.3,0.5,-0.4)
        $OM frame "${terrain[@]}" -o "$tmp/truth-terrain"
        cp "$tmp/truth-terrain/frame.json" "$DATA/truth-terrain.json"
        $OM frame "${terrain[@]}" --method exact -o "$tmp/truth-terrain-exact"
        cp "$tmp/truth-terrain-exact/frame.json" "$DATA/truth-terrain-exact.json"
        rm -rf "$tmp/kernels-axis" && cp -r kernels "$tmp/kernels-axis"
        sed -i 's/const OmF ra = \*a - d \* nt, rb = \*b - d \* nb;/const OmF ra = *a, rb = *b;/' \
            "$tmp/kernels-axis/common/triplanar.cl"
        grep -q 'const OmF ra = \*a, rb = \*b;' "$tmp/kernels-axis/common/triplanar.cl"
        OFFSETMAP_KERNEL_DIR="$tmp/kernels-axis" $OM frame "${terrain[@]}" -o "$tmp/truth-terrain-axis"
        cp "$tmp/truth-terrain-axis/frame.json" "$DATA/truth-terrain-axis-ray.json"
        # the two uv error maps (the truth sheet's first tile: 6 px in, under a 28 px label)
        for run in truth-terrain truth-terrain-axis; do
            /usr/bin/python3 -c 'import sys; from PIL import Image
Image.open(sys.argv[1]).crop((6, 34, 646, 394)).save(sys.argv[2])' \
                "$tmp/$run/truth-sheet.png" "$tmp/$run/uv-error.png"
        done
        /usr/bin/python3 docs/crop_figure.py "$IMG/truth-terrain.png" 0 100 640 330 1 \
            "$tmp/truth-terrain-axis/uv-error.png" "uv error, rays over the projection's plane" \
            "$tmp/truth-terrain/uv-error.png" "rays over the surface (log, white = 16 texels)" \
            "$tmp/truth-terrain/triplanar.png" "projections traced: one, two, three"
        # the curved trace's model against the truth, without a march's own error (docs/design.md)
        $OM frame --scene data/curved.gltf --width 960 --height 540 --truth --curvature \
            --layers 2 --method exact -o "$tmp/truth-curved-exact"
        cp "$tmp/truth-curved-exact/frame.json" "$DATA/truth-curved-exact.json"
        # relief above the polygon (r = 0.5): what the base mesh's outline cannot give
        sed -e 's#"height_map": "#"height_map": "'"$PWD"'/data/#' \
            -e 's#"scale": \([0-9.]*\),#"scale": \1, "reference_plane": 0.5,#' \
            data/curved.json >"$tmp/curved-r05.json"
        $OM frame --scene data/curved.gltf --materials "$tmp/curved-r05.json" --width 960 \
            --height 540 --truth --curvature --layers 2 --method exact -o "$tmp/truth-curved-r05"
        cp "$tmp/truth-curved-r05/frame.json" "$DATA/truth-curved-r05.json"
        ;;
    rebuild)  # a field that changes every frame: its update and each precompute's rebuild, on
        # PoCL's AVX-512 and AVX2 targets (docs/integrating.md)
        ./build/release/offsetmap_bench --rebuild --out "$tmp/rebuild"
        cp "$tmp/rebuild/bench-rebuild.json" "$DATA/bench-rebuild.json"
        POCL_KERNELLIB_NAME=avx2 POCL_LLVM_CPU_NAME=znver3 \
            ./build/release/offsetmap_bench --rebuild --out "$tmp/rebuild-avx2"
        cp "$tmp/rebuild-avx2/bench-rebuild.json" "$DATA/bench-rebuild-avx2.json"
        ;;
    *) echo "regenerate.sh: unknown part '$part'" >&2; exit 2 ;;
    esac
done
lscpu | sed -n 's/^Model name: *//p;s/^Flags:.*\(avx512f\).*/AVX-512/p' >"$DATA/machine.txt"
echo "regenerate.sh: wrote $DATA and $IMG"
