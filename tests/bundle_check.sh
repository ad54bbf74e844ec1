#!/usr/bin/env bash
# bundle_check.sh TARBALL : the device check's bundle as a machine with a driver and nothing else
# meets it: unpacked in a fresh folder and run with an empty environment (nothing of the build on
# any path), on PoCL through the system's registered driver, with no driver registered (the
# script then finds the vendors' libraries itself), and on rusticl. At most 40 MiB.
# bundle_check.sh --loader TARBALL N : only the loader check below, N times (ctest runs it under
# load: bundle.loader_check_under_load).
set -uo pipefail
repeats=
if [ "$1" = --loader ]; then
    repeats=$3
    shift
fi
tarball=$(realpath "$1")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
tar -C "$tmp" -xzf "$tarball"
dir=$tmp/offsetmap-check
# The check finds no ICD loader of the system's (a machine with a driver but no loader), or
# loads the bundle's. ldd's whole output is read after it ends: `ldd | grep -q` under pipefail
# fails whenever grep stops at its first match before ldd has written its last line (ldd then
# dies of SIGPIPE; on a loaded machine 5 runs in 200 did).
loader_check() {
    local plain bundled
    plain=$(ldd "$dir/bin/offsetmap_check" 2>&1)
    bundled=$(LD_LIBRARY_PATH=$dir/lib ldd "$dir/bin/offsetmap_check" 2>&1)
    grep -q "not found" <<<"$plain" || grep -qF "$dir/lib/libOpenCL.so.1" <<<"$bundled"
}
if [ -n "$repeats" ]; then
    for ((k = 1; k <= repeats; ++k)); do
        loader_check || fails=$((fails + 1))
    done
    echo "the loader check: $((repeats - fails)) of $repeats runs passed"
    [ $fails -eq 0 ]
    exit
fi
size=$(du -k "$tarball" | cut -f1)
[ "$size" -le $((40 * 1024)) ] || fail "the bundle is $size KiB, over 40 MiB"
echo "bundle: $size KiB; $(cd "$dir" && find . -type f | sort | tr '\n' ' ')"
loader_check || fail "the check does not load the bundle's ICD loader"
cd "$tmp"
# PoCL, registered in /etc/OpenCL/vendors.
env -i /bin/sh "$dir/check" --quick --device "portable computing" --json "$tmp/pocl.json" \
    >"$tmp/pocl.out" 2>"$tmp/pocl.err"
rc=$?
if [ $rc -ne 0 ] || ! grep -q "OpenCL drivers registered in /etc/OpenCL/vendors" "$tmp/pocl.err" ||
    ! grep -q '"failures": 0' "$tmp/pocl.json"; then
    fail "PoCL from an empty environment (exit $rc)"; tail -5 "$tmp/pocl.err"
else
    echo "ok PoCL from an empty environment: $(grep -E 'cases, ' "$tmp/pocl.out")"
fi
# No driver registered: the script finds PoCL's library itself.
mkdir -p "$tmp/no-vendors"
env -i OCL_ICD_VENDORS="$tmp/no-vendors" /bin/sh "$dir/check" --list >"$tmp/found.out" \
    2>"$tmp/found.err"
rc=$?
if [ $rc -ne 0 ] || ! grep -q "no OpenCL driver is registered .*libpocl.so" "$tmp/found.err" ||
    ! grep -q "^Portable Computing Language" "$tmp/found.out"; then
    fail "no driver registered (exit $rc)"; cat "$tmp/found.err"
else
    echo "ok no driver registered: $(head -1 "$tmp/found.err")"
fi
# rusticl over llvmpipe.
env -i RUSTICL_ENABLE=llvmpipe /bin/sh "$dir/check" --quick --device llvmpipe \
    >"$tmp/rusticl.out" 2>"$tmp/rusticl.err"
rc=$?
if [ $rc -ne 0 ]; then
    fail "rusticl from an empty environment (exit $rc)"; tail -5 "$tmp/rusticl.err"
else
    echo "ok rusticl from an empty environment: $(grep -E 'cases, ' "$tmp/rusticl.out")"
fi
[ $fails -eq 0 ]
