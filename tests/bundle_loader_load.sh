#!/usr/bin/env bash
# bundle_loader_load.sh CHECK WORK : tests/bundle_check.sh's loader check, 200 times on a loaded
# machine (a busy loop a core beside it), over a bundle laid out as ./run bundle lays it out: the
# check binary and an ICD loader in lib/. Its `ldd | grep -q` under pipefail failed there about
# once in forty runs (ldd killed by SIGPIPE when grep had stopped at its match).
set -euo pipefail
check=$1 work=$2
rm -rf "$work" && mkdir -p "$work/offsetmap-check/bin" "$work/offsetmap-check/lib"
cp "$check" "$work/offsetmap-check/bin/offsetmap_check"
libs=$(ldd "$check")
loader=$(awk '$1 == "libOpenCL.so.1" {print $3}' <<<"$libs")
[ -n "$loader" ] || { echo "bundle_loader_load: $check links no libOpenCL.so.1"; exit 1; }
cp "$loader" "$work/offsetmap-check/lib/libOpenCL.so.1"
tar -C "$work" -czf "$work/bundle.tar.gz" offsetmap-check
busy=()
trap 'kill "${busy[@]}" 2>/dev/null || true' EXIT
for ((k = 0; k < $(nproc); ++k)); do
    (while :; do :; done) &
    busy+=($!)
done
bash "$(dirname "$0")/bundle_check.sh" --loader "$work/bundle.tar.gz" 200
