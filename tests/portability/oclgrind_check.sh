#!/usr/bin/env bash
# Oclgrind over the CLI's passes on a small frame: every report in its log fails the check
# (Oclgrind exits 0 whatever it finds, so the log is read). One pixel a work-item (the GPU path)
# with --data-races --uninitialized --check-api; at 16 lanes without --uninitialized, whose
# plugin in Oclgrind 21.10 crashes on any vector concatenation ((float8)(a4, b4)). Built with
# -cl-opt-disable -DOM_PLAIN_CALLS: optimised, Oclgrind 21.10 mis-evaluates `xor <N x i1>, true`
# (a vector `!` gives -2, not 0) and cannot run freeze, llvm.ctpop or
# llvm.experimental.noalias.scope.decl (docs/design.md, "Portability").
#   oclgrind_check.sh OFFSETMAP_CLI MAP WORK_DIR
set -uo pipefail
om=$1 map=$2 work=$3
mkdir -p "$work"
command -v oclgrind >/dev/null || { echo "oclgrind_check: oclgrind is not installed" >&2; exit 1; }
fails=0 runs=0
run_case() {
    local name=$1 lanes=$2 plugins=$3
    shift 3
    local log="$work/$name.log"
    rm -f "$log"
    OFFSETMAP_LANES=$lanes timeout 600 oclgrind --build-options "-cl-opt-disable -DOM_PLAIN_CALLS" \
        $plugins --log "$log" "$om" "$@" >"$work/$name.out" 2>&1
    local rc=$? reports=0
    [ -f "$log" ] && reports=$(grep -cE "^(Uninitialized|Invalid|Read-write|Write-write|Oclgrind|OCLGRIND|Work-group divergence|Data race)" "$log")
    runs=$((runs + 1))
    if [ $rc -ne 0 ] || [ "$reports" -ne 0 ]; then
        fails=$((fails + 1))
        echo "FAIL $name (lanes $lanes): exit $rc, $reports reports"
        head -12 "$log" 2>/dev/null
        tail -3 "$work/$name.out"
    else
        echo "ok $name (lanes $lanes): 0 reports"
    fi
}
all="--data-races --uninitialized --check-api"
noinit="--data-races --check-api"
frame=(--height-map "$map" --width 19 --height 13)
for m in none parallax parallax-iterative steep pom relief secant cone maxmip sphere exact; do
    run_case "$m-wrap" 1 "$all" render --method "$m" "${frame[@]}"
done
run_case pom-clamp-float-lod 1 "$all" render --method pom "${frame[@]}" --address clamp \
    --height-storage float --lod-threshold 2
OFFSETMAP_IMAGES=1 run_case pom-images 1 "$all" render --method pom "${frame[@]}"
run_case shade-hard 1 "$all" render --method pom "${frame[@]}" --shadows hard --color-out "$work/h.png"
run_case shade-soft 1 "$all" render --method relief "${frame[@]}" --shadows soft --color-out "$work/s.png"
run_case random-exact 1 "$all" render --method exact --scene random --width 17 --height 11 \
    --height-map "$map"
for m in pom cone exact; do
    run_case "$m-lanes16" 16 "$noinit" render --method "$m" "${frame[@]}"
done
echo "$((runs - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
