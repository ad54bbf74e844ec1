#!/bin/sh
# offsetmap's device check, unpacked anywhere on a Linux x86-64 machine (glibc 2.34 or newer) with
# an OpenCL driver; no package, network or root needed, the OpenCL ICD loader comes with it:
#   ./check [--quick] [--device TEXT] [--json FILE] ...      (./check --help for every option)
# Where the system registers no OpenCL driver (no .icd file in /etc/OpenCL/vendors, or where
# OCL_ICD_VENDORS points), it looks for the vendors' libraries (NVIDIA, AMD, Intel, PoCL, Mesa) in
# the usual folders and ldconfig's cache, and points the loader at what it finds. It says which
# drivers it uses on stderr, first.
PATH=${PATH:-/usr/bin:/bin}
export PATH
here=$(cd "$(dirname "$0")" && pwd)
LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export LD_LIBRARY_PATH

glibc=$(getconf GNU_LIBC_VERSION 2>/dev/null | sed 's/^glibc //')
case $glibc in
"" | 2.3[4-9]* | 2.[4-9][0-9]* | [3-9].*) ;;
*)
    echo "check: this build needs glibc 2.34 or newer; this machine has $glibc" >&2
    exit 1
    ;;
esac

vendors=${OCL_ICD_VENDORS:-/etc/OpenCL/vendors}
registered=""
if [ -d "$vendors" ]; then
    for f in "$vendors"/*.icd; do
        [ -e "$f" ] && registered="$registered $(basename "$f")"
    done
elif [ -f "$vendors" ]; then
    registered=" $vendors"
fi
if [ -n "${OCL_ICD_FILENAMES:-}" ]; then
    echo "check: OpenCL drivers from OCL_ICD_FILENAMES: $OCL_ICD_FILENAMES" >&2
elif [ -n "$registered" ]; then
    echo "check: OpenCL drivers registered in $vendors:$registered" >&2
else
    found=""
    for name in libnvidia-opencl.so.1 libamdocl64.so libamdocl-orca64.so libigdrcl.so \
        libintelocl.so libpocl.so.2 libRusticlOpenCL.so.1 libMesaOpenCL.so.1; do
        path=""
        for dir in /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib /usr/local/lib /usr/local/lib64 \
            /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/lib/x86_64-linux-gnu/nvidia/current \
            /usr/lib/wsl/lib /opt/rocm/lib /opt/rocm/opencl/lib /opt/amdgpu-pro/lib64 \
            /usr/lib/x86_64-linux-gnu/intel-opencl /opt/intel/oneapi/lib; do
            if [ -e "$dir/$name" ]; then
                path=$dir/$name
                break
            fi
        done
        if [ -z "$path" ] && command -v ldconfig >/dev/null 2>&1; then
            path=$(ldconfig -p 2>/dev/null | awk -v n="$name" '$1 == n && /x86-64/ && !p {print $NF; p = 1}')
        fi
        [ -n "$path" ] && found="${found:+$found:}$path"
    done
    if [ -z "$found" ]; then
        echo "check: no OpenCL driver is registered ($vendors holds no .icd file) and none of" \
            "the known vendors' libraries was found; install the GPU's OpenCL driver, or set" \
            "OCL_ICD_FILENAMES to its library" >&2
        exit 1
    fi
    echo "check: no OpenCL driver is registered in $vendors; using $found" >&2
    OCL_ICD_FILENAMES=$found
    export OCL_ICD_FILENAMES
    unset OCL_ICD_VENDORS  # the loader reads these libraries instead, not an empty folder
fi
exec "$here/bin/offsetmap_check" "$@"
