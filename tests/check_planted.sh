#!/usr/bin/env bash
# check_planted.sh CHECK KERNELS WORK : the device check catches a kernel broken on purpose. Each
# planted bug (a copy of KERNELS with one edit, loaded through OFFSETMAP_KERNEL_DIR) must make
# `CHECK --quick --no-timing --methods M` exit 1 with a failure line naming M (or the pass it
# broke); the unedited copy must pass.
set -uo pipefail
check=$1 kernels=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fails=0
run() {  # NAME METHOD FILE FIND REPLACE [KERNEL] (empty FIND: the copy unedited, which must pass)
    local name=$1 method=$2 file=$3 find=$4 replace=$5 kernel=${6:-$2} dir="$work/$1"
    cp -r "$kernels" "$dir"
    if [ -n "$find" ]; then
        FIND=$find REPLACE=$replace /usr/bin/python3 - "$dir/$file" <<'PY' || { fails=$((fails + 1)); return; }
import os, sys
path = sys.argv[1]
text = open(path).read()
if text.count(os.environ["FIND"]) != 1:
    sys.exit(f"check_planted: the edit no longer applies to {path}")
open(path, "w").write(text.replace(os.environ["FIND"], os.environ["REPLACE"]))
PY
    fi
    OFFSETMAP_KERNEL_DIR=$dir "$check" --quick --no-timing --methods "$method" \
        >"$work/$name.out" 2>"$work/$name.err"
    local rc=$?
    if [ -z "$find" ]; then
        if [ $rc -ne 0 ]; then
            echo "FAIL $name: the unedited kernels failed (exit $rc)"; cat "$work/$name.err"
            fails=$((fails + 1))
        else
            echo "ok $name: passes"
        fi
    elif [ $rc -eq 1 ] && grep -q "^FAIL .*: $kernel, " "$work/$name.err"; then
        echo "ok $name: caught ($(grep -c '^FAIL' "$work/$name.err") failure lines, e.g.)"
        grep -m1 '^FAIL' "$work/$name.err"
    else
        echo "FAIL $name: not caught (exit $rc)"; tail -5 "$work/$name.err"
        fails=$((fails + 1))
    fi
}
run unedited pom,cone methods/pom.cl "" ""
# pom's segment cut with its two gaps swapped: an approximate method, caught against the C++ peer
# (compiled from the library's own kernels when the check was built).
run pom-cut-swapped pom methods/pom.cl "om_segment_cut(l0, l1, d0, d1)" "om_segment_cut(l0, l1, d1, d0)"
# cone's step without the ray's descent in its denominator: steps past the hit (an exact walk,
# against the oracle).
run cone-step-too-long cone methods/cone.cl \
    "OmF t_cone = t + c * (r->ref - t * down - hc) / (s->across + c * down);" \
    "OmF t_cone = t + c * (r->ref - t * down - hc) / s->across;"
# The shade pass's self-shadow march with each sample's slope measured one step too far: shadows
# a little short, caught against the shade kernel compiled as C++.
run shadow-slope-short pom shade.cl \
    "const OmF rise = (h - h0) * ((float)n / fi);" \
    "const OmF rise = (h - h0) * ((float)n / (fi + 1.0f));" shade
[ $fails -eq 0 ]
