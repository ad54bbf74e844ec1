#!/usr/bin/env bash
# Oclgrind over every kernel entry the CLI reaches, on a small odd-sized frame and map: wrap and
# clamp, unorm16 words and float heights, images and buffers, LOD, every method, the material
# frame (id 0 and a missing id beside two materials), the engine-form reconstruction, shading
# with hard and soft shadows, the rendered frame's pixel depth offset, the curved trace and the
# material frame's layer behind; one pixel a work-item (a GPU's path) and 16 (PoCL's).
# Oclgrind exits 0 whatever it finds, so its log is read: each report opens with a line at column
# 0 (its details are indented), and any such line fails the case.
# Plugins: --data-races --check-api, beside Oclgrind's own checks of every access against its
# buffer's bounds; --uninitialized too on the one-map runs of `none` (import, mips, unorm16 words,
# normals, reconstruction, shading): elsewhere Oclgrind 21.10's plugin reports values that are
# provably written, and at 16 lanes it crashes (docs/design.md, "Portability"). Run as a user runs
# it, with no build options of its own: on Oclgrind the runtime builds every program unoptimised
# with its helpers as calls (-cl-opt-disable, OM_PLAIN_CALLS), since optimised Oclgrind 21.10
# mis-evaluates `xor <N x i1>, true` (a vector `!` gives -2, not 0) and cannot run freeze,
# llvm.ctpop or llvm.experimental.noalias.scope.decl.
#   oclgrind_check.sh OFFSETMAP_CLI MAP WORK_DIR [CASE_FILTER | sample [TESTS]]
# TESTS, the suite's binary, runs the kernels no CLI command reaches without a GL context (the
# rendered frame cannot run under Oclgrind: its LLVM beside llvmpipe's aborts the process).
# CASE_FILTER, a regular expression, picks cases by name; `sample` picks `./run test`'s: each
# method at one lane on buffers, a case for every other kernel entry, and the room's material
# frame; the sweep (no filter) runs every case.
set -uo pipefail
om=$1 map=$(realpath "$2") work=$3 only=${4:-} tests=${5:-}
root=$(cd "$(dirname "$0")/../.." && pwd)
methods="none parallax parallax-limited parallax-slope parallax-iterative steep relief pom secant \
cone maxmip exact sphere"
if [ "$only" = sample ]; then
    only="^($(tr -s ' ' '|' <<<"$methods")|none-uninit|none-float-clamp-lod-uninit"
    only+="|shade-hard-uninit|shade-soft|gbuffer-engine|engine-form-uninit|gbuffer-ids|materials"
    only+="|room|room-uninit|gbuffer-curved|curved-exact|depth-offset|shadow-mask|triplanar-1"
    only+="|layer-behind)$"
fi
mkdir -p "$work"
command -v oclgrind >/dev/null || { echo "oclgrind_check: oclgrind is not installed" >&2; exit 1; }
fails=0 runs=0
run_case() {
    local name=$1 lanes=$2
    shift 2
    [ -n "$only" ] && [[ ! $name =~ $only ]] && return 0
    local log="$work/$name.log" start=$SECONDS
    rm -f "$log"
    # shellcheck disable=SC2086  # $uninit is one flag or none
    OFFSETMAP_LANES=$lanes timeout 900 oclgrind --data-races --check-api ${uninit:-} \
        --log "$log" "${bin:-$om}" "$@" >"$work/$name.out" 2>&1
    local rc=$? reports=0
    [ -f "$log" ] && reports=$(grep -c '^[^[:space:]]' "$log")
    # A check of a wrong execution proves nothing: a render's pixel and fetch counts must be the
    # default device's (PoCL here) for the same command.
    local stats="" expected=""
    if [ "$1" = render ]; then
        stats=$(grep -oE '[0-9]+ traced, [0-9.]+ fetches/pixel' "$work/$name.out")
        expected=$(OFFSETMAP_LANES=$lanes "$om" "$@" 2>/dev/null |
            grep -oE '[0-9]+ traced, [0-9.]+ fetches/pixel')
    fi
    # The suite's binary tears its runtime down after Oclgrind's at exit, which aborts there: a
    # test case is judged by gtest's verdict (and the log) instead of the exit status.
    if [ -n "${bin:-}" ] && grep -q '^\[  PASSED  \] 1 test' "$work/$name.out"; then rc=0; fi
    runs=$((runs + 1))
    if [ $rc -ne 0 ] || [ "$reports" -ne 0 ] || [ "$stats" != "$expected" ]; then
        fails=$((fails + 1))
        echo "FAIL $name (lanes $lanes, $((SECONDS - start)) s): exit $rc, $reports reports," \
            "Oclgrind '$stats', default device '$expected'"
        head -12 "$log" 2>/dev/null
        tail -3 "$work/$name.out"
    else
        echo "ok $name (lanes $lanes, $((SECONDS - start)) s): 0 reports"
    fi
}
frame=(--height-map "$map" --width 19 --height 13)
# Every method at one pixel a work-item on buffers and on images, and at 16 pixels. Sphere's
# distance map at its default 256 x 256 x 32 voxels would take Oclgrind hours: 16 x 16 x 4 here.
for m in $methods; do
    set=()
    [ "$m" = sphere ] && set=(--set res=16 --set layers=4)
    run_case "$m" 1 render --method "$m" "${frame[@]}" "${set[@]}"
    OFFSETMAP_IMAGES=1 run_case "$m-images" 1 render --method "$m" "${frame[@]}" "${set[@]}"
    run_case "$m-lanes16" 16 render --method "$m" "${frame[@]}" "${set[@]}"
done
# Every value the preparation kernels, the reconstruction and the shade pass write is initialised.
uninit=--uninitialized run_case none-uninit 1 render --method none "${frame[@]}"
uninit=--uninitialized OFFSETMAP_IMAGES=1 run_case none-images-uninit 1 render --method none \
    "${frame[@]}"
uninit=--uninitialized run_case none-float-clamp-lod-uninit 1 render --method none "${frame[@]}" \
    --height-storage float --address clamp --lod-threshold 2
uninit=--uninitialized run_case shade-hard-uninit 1 render --method none "${frame[@]}" \
    --shadows hard --color-out "$work/hn.png"
run_case pom-clamp-float-lod 1 render --method pom "${frame[@]}" --address clamp \
    --height-storage float --lod-threshold 2
# pom's spacing rule, which reads each lane's mip level size under LOD.
run_case pom-spacing-lod 1 render --method pom "${frame[@]}" --set spacing=2 --lod-threshold 2
run_case pom-spacing-lod-lanes16 16 render --method pom "${frame[@]}" --set spacing=2 \
    --lod-threshold 2
run_case exact-clamp-float 1 render --method exact "${frame[@]}" --address clamp \
    --height-storage float
OFFSETMAP_IMAGES=1 run_case cone-images-clamp 1 render --method cone "${frame[@]}" --address clamp
# The beam (common/beam.cl) needs sides a multiple of 2: a 32 x 16 crop of rocks.png, a frame
# whose work-items' rays skip together, and at one lane one ray's beam; clamp reads edge blocks.
even=(--height-map "$root/tests/portability/even32x16.png" --width 19 --height 13)
for lanes in 1 16; do
    run_case cone-beam-lanes$lanes $lanes render --method cone --set beam=1 "${even[@]}"
    run_case maxmip-beam-clamp-lanes$lanes $lanes render --method maxmip --set beam=1 \
        "${even[@]}" --address clamp
done
run_case shade-hard 1 render --method pom "${frame[@]}" --shadows hard --color-out "$work/h.png"
run_case shade-soft 1 render --method relief "${frame[@]}" --shadows soft --color-out "$work/s.png"
run_case random-exact 1 render --method exact --scene random --width 17 --height 11 \
    --height-map "$map"
# A material frame: ids 0 (no material), 1 and 3 of a two-material table, shaded.
cat >"$work/materials.json" <<EOF
[{"id": 1, "height_map": "$map", "method": "pom", "params": {"min_samples": 4}},
 {"id": 3, "height_map": "$map", "scale": 0.03, "method": "cone", "address": "clamp"}]
EOF
run_case gbuffer-ids 1 gbuffer --width 19 --height 13 --material-ids 0 1 3 -o "$work/ids.exr"
run_case materials 1 render --materials "$work/materials.json" --gbuffer "$work/ids.exr" \
    --color-out "$work/m.png"
OFFSETMAP_IMAGES=1 run_case materials-images 1 render --materials "$work/materials.json" \
    --gbuffer "$work/ids.exr"
# The room's material table (five materials, three methods) as a user renders it, each material's
# map the small one (its own maps take Oclgrind minutes); and the same with no method that samples
# the relief under --uninitialized (the plugin's false reports on the patch corners, below, come
# from any such method): every value the uploads, the gather, the classification and the
# materials' shade write is initialised.
small_maps="s#\"height_map\": \"[^\"]*\"#\"height_map\": \"$map\"#"
no_relief='s/"method": "[a-z-]*", "params": \{[^}]*\}/"method": "none"/'
sed -E -e "$small_maps" "$root/data/room.json" >"$work/room.json"
sed -E -e "$small_maps" -e "$no_relief" "$root/data/room.json" >"$work/room-none.json"
run_case room 1 render --materials "$work/room.json" --scene plane --width 24 --height 16 \
    --uv-out "$work/room.exr" --color-out "$work/room.png"
uninit=--uninitialized run_case room-uninit 1 render --materials "$work/room-none.json" \
    --scene plane --width 24 --height 16 --uv-out "$work/room-none.exr" \
    --color-out "$work/room-none.png"
# The engine form (depth, camera and frame) goes through the reconstruction kernel.
run_case gbuffer-engine 1 gbuffer --engine-form reversed --width 19 --height 13 -o "$work/e.exr"
run_case engine-form 1 render --gbuffer "$work/e.exr" --height-map "$map" --method relief
uninit=--uninitialized run_case engine-form-uninit 1 render --gbuffer "$work/e.exr" \
    --height-map "$map" --method none
run_case pom-lanes8 8 render --method pom "${frame[@]}"
run_case exact-lanes8 8 render --method exact "${frame[@]}"
run_case materials-lanes16 16 render --materials "$work/materials.json" --gbuffer "$work/ids.exr" \
    --color-out "$work/m16.png"
run_case shade-soft-lanes16 16 render --method relief "${frame[@]}" --shadows soft \
    --color-out "$work/s16.png"
# The rendered frame's pixel depth offset, through the suite's test of its kernel.
[ -n "$tests" ] && bin=$tests run_case depth-offset 1 \
    --gtest_filter=DepthOffset.KernelMovesEachPointAlongItsEyeRay
# The material frame's layer behind (its mask, choice and plane copies), through the suite's test.
# The uv metric's planes beside the curvature (every kind of base: a skewed patch, a uv sphere
# toward its pole, every term at once): the walk, the march and the slope step.
for lanes in 1 16; do
    [ -n "$tests" ] && bin=$tests run_case uv-metric-lanes$lanes $lanes \
        --gtest_filter=UvMetric.ASmallFrameMeetsTheOracle
done
[ -n "$tests" ] && bin=$tests run_case layer-behind 1 \
    --gtest_filter=MaterialFrame.LayerBehindShowsWhatTheFirstLayerDoesNot
# The receivers' shadow test (its receiver plane, filter taps past the map's edges), one pixel a
# work-item and in 16 lanes (the vector projections, the gathers and the row's last lanes).
[ -n "$tests" ] && bin=$tests run_case shadow-mask 1 \
    --gtest_filter=ShadowMask.SmallFrameWithTapsPastTheMapsEdges
[ -n "$tests" ] && bin=$tests run_case shadow-mask-lanes16 16 \
    --gtest_filter=ShadowMask.SmallFrameWithTapsPastTheMapsEdges
# A spot light: its cone in the reconstruct pass and the shade's dimming; a perspective map with
# points behind the light, at 1 and 16 lanes.
for lanes in 1 16; do
    [ -n "$tests" ] && bin=$tests run_case spot-light-$lanes $lanes \
        --gtest_filter=EngineGBuffer.SpotLightIsAPointLightWithinItsCone
    [ -n "$tests" ] && bin=$tests run_case shadow-mask-spot-$lanes $lanes \
        --gtest_filter=ShadowMask.PointsBehindASpotLightAreOutsideItsMap
done
# The shade pass with a shadow mask beside the march, and the visibility it writes.
for lanes in 1 16; do
    [ -n "$tests" ] && bin=$tests run_case shade-shadow-mask-$lanes $lanes \
        --gtest_filter=Shadows.AShadowMapAndTheMarchDarkenAPixelOnceByTheStricter
done
# Triplanar: the reconstruct pass's split, the projections' traces, the merge and the blended
# shade, through the suite's test of the merge.
for lanes in 1 16; do
    [ -n "$tests" ] && bin=$tests run_case triplanar-$lanes $lanes \
        --gtest_filter=Triplanar.ABlendMergesDepthAndFetches
done
run_case engine-form-lanes16 16 render --gbuffer "$work/e.exr" --height-map "$map" --method pom
# Over a curved base (the G-buffer's curvature channels, a sphere of a quarter tile's radius with a
# stretched uv and a saddle): the cell walks, a march and the material frame's tiles, at 1 and 16
# lanes, on buffers and images, in both G-buffer forms.
run_case gbuffer-curved 1 gbuffer --width 19 --height 13 --curvature 4 0 4 1.3 -o "$work/c.exr"
run_case gbuffer-curved-engine 1 gbuffer --engine-form gl --width 19 --height 13 \
    --curvature 2 1 -3 -o "$work/ce.exr"
run_case gbuffer-curved-ids 1 gbuffer --width 19 --height 13 --material-ids 0 1 3 \
    --curvature 4 0 4 -o "$work/cids.exr"
run_case curved-exact 1 render --gbuffer "$work/c.exr" --height-map "$map" --method exact
OFFSETMAP_IMAGES=1 run_case curved-cone-images 1 render --gbuffer "$work/c.exr" \
    --height-map "$map" --method cone
run_case curved-pom-lanes16 16 render --gbuffer "$work/c.exr" --height-map "$map" --method pom
run_case curved-maxmip-engine-lanes16 16 render --gbuffer "$work/ce.exr" --height-map "$map" \
    --method maxmip
run_case curved-materials 1 render --materials "$work/materials.json" --gbuffer "$work/cids.exr" \
    --color-out "$work/cm.png"
run_case curved-materials-lanes16 16 render --materials "$work/materials.json" \
    --gbuffer "$work/cids.exr"
echo "$((runs - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
