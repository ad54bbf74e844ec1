#!/usr/bin/env bash
# The SPIR-V portability gate: every program variant (offsetmap_programs) compiled offline as a
# SPIR-V driver compiles it (clang-15 to LLVM IR for spir64, OpenCL C 1.2, cl_khr_fp64 off, every
# warning an error; llvm-spirv-15 to SPIR-V) and checked by spirv-val. A double, a 64-bit float
# capability, an LLVM intrinsic the translator rejects (llvm.vector.reduce.*) or an extension
# outside ALLOWED fails it. Two front-end modes: the LLVM passes at -O0 (always_inline still
# inlines), and with the passes off (nothing inlined: every helper must have a body). With
# --sample, only the sample (one default variant a kernel file, `./run test`'s tier).
#   spirv_gate.sh PROGRAMS_TOOL [WORK_DIR [--sample]]
set -euo pipefail
tool=$1
work=${2:-$(mktemp -d)}
sample=${3:-}
ALLOWED=""  # OpExtension names a variant may use: none (plain OpenCL C 1.2)
for t in clang-15 llvm-spirv-15 spirv-val spirv-dis; do
    command -v "$t" >/dev/null || { echo "spirv_gate: $t is not installed" >&2; exit 1; }
done
rm -rf "$work/src" "$work/out"
mkdir -p "$work/out"
# shellcheck disable=SC2086  # $sample is one flag or none
"$tool" $sample "$work/src"
check_one() {
    local file=$1 src=$2 out=$3 allowed=$4
    local stem=${file%.cl}
    for mode in O0 nopasses; do
        local opt="-O0"
        [ "$mode" = nopasses ] && opt="-O2 -Xclang -disable-llvm-passes"
        local bc="$out/$stem.$mode.bc" spv="$out/$stem.$mode.spv" log="$out/$stem.$mode.log"
        # shellcheck disable=SC2086
        if ! clang-15 -x cl -cl-std=CL1.2 -target spir64 $opt -Xclang -finclude-default-header \
            -Xclang -cl-ext=-cl_khr_fp64 -Werror -emit-llvm -c "$src/$file" -o "$bc" >"$log" 2>&1; then
            echo "FAIL $file ($mode): clang: $(grep -m1 -E 'error' "$log")"
            return 0
        fi
        if ! llvm-spirv-15 "$bc" -o "$spv" >>"$log" 2>&1; then
            echo "FAIL $file ($mode): llvm-spirv: $(head -c 300 "$log" | tr '\n' ' ')"
            return 0
        fi
        if ! spirv-val "$spv" >>"$log" 2>&1; then
            echo "FAIL $file ($mode): spirv-val: $(grep -m1 error "$log")"
            return 0
        fi
        local dis
        dis=$(spirv-dis "$spv")
        if grep -qE "OpCapability (Float64|Int64Atomics)|OpTypeFloat 64" <<<"$dis"; then
            echo "FAIL $file ($mode): uses 64-bit floats or 64-bit atomics"
            return 0
        fi
        local ext
        for ext in $(grep -oE 'OpExtension "[^"]+"' <<<"$dis" | cut -d'"' -f2); do
            case " $allowed " in
                *" $ext "*) ;;
                *) echo "FAIL $file ($mode): extension $ext"; return 0 ;;
            esac
        done
        rm -f "$bc" "$spv" "$log"
    done
    echo "ok $file"
}
export -f check_one
cut -d' ' -f1 "$work/src/index.txt" |
    xargs -P "$(nproc)" -I{} bash -c 'check_one "$@"' _ {} "$work/src" "$work/out" "$ALLOWED" \
        >"$work/results.txt"
total=$(wc -l <"$work/results.txt")
failed=$(grep -c '^FAIL' "$work/results.txt" || true)
grep '^FAIL' "$work/results.txt" | sed -n 1,20p || true
echo "spirv_gate: $((total - failed)) of $total program variants compiled to valid SPIR-V (2 modes each)"
[ "$failed" -eq 0 ] && [ "$total" -gt 0 ]
