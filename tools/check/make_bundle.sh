#!/usr/bin/env bash
# make_bundle.sh CHECK OUT : the device check's offline bundle from a build of it (the "bundle"
# preset): OUT/offsetmap-check/ (the `check` script, bin/offsetmap_check with its kernels
# embedded, lib/libOpenCL.so.1, the ICD loader it links, and README.txt) and
# OUT/offsetmap-check.tar.gz of the same.
set -euo pipefail
check=$1 out=$2
src=$(cd "$(dirname "$0")" && pwd)
dir=$out/offsetmap-check
rm -rf "$dir" "$out/offsetmap-check.tar.gz"
mkdir -p "$dir/bin" "$dir/lib"
cp "$check" "$dir/bin/offsetmap_check"
strip "$dir/bin/offsetmap_check"
loader=$(ldd "$check" | awk '$1 == "libOpenCL.so.1" {print $3}')
[ -n "$loader" ] || { echo "make_bundle: $check does not link libOpenCL.so.1" >&2; exit 1; }
cp -L "$loader" "$dir/lib/libOpenCL.so.1"
cp "$src/check.sh" "$dir/check"
chmod +x "$dir/check"
cat >"$dir/README.txt" <<TEXT
offsetmap's device check: every kernel of the pass on this machine's OpenCL devices against its
CPU reference, and each method's speed there. Linux x86-64, glibc 2.34 or newer, an OpenCL
driver; nothing else (the OpenCL ICD loader is in lib/).

    ./check                       every device, the full check (about 2 minutes on a 2-core CPU)
    ./check --quick               smaller cases (about 20 s)
    ./check --device nvidia --json result.json
    ./check --help

Exit status 0 when every case passed; 1 with one line per failure on stderr. What to send back
when it fails: the whole output and the --json file.
Built from offsetmap $(git -C "$src" rev-parse --short HEAD 2>/dev/null || echo "(unknown)")
on $(date -u +%Y-%m-%d).
TEXT
tar -C "$out" -czf "$out/offsetmap-check.tar.gz" offsetmap-check
echo "bundle: $dir and $out/offsetmap-check.tar.gz ($(du -k "$out/offsetmap-check.tar.gz" | cut -f1) KiB)"
