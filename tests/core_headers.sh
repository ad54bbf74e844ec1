#!/usr/bin/env bash
# core_headers.sh CXX DIR... : with the core's include directories DIR (offsetmap::offsetmap's
# interface, empty entries ignored), its umbrella header compiles and no header of the lab or the
# renderer is found: an engine that links the core sees no other target's headers.
set -euo pipefail
cxx=$1; shift
flags=(-std=c++17 -fsyntax-only -x c++)
for d in "$@"; do [ -n "$d" ] && flags+=(-I "$d"); done
echo '#include "offsetmap/offsetmap.hpp"' | "$cxx" "${flags[@]}" - ||
    { echo "the core's own header does not compile with its include directories"; exit 1; }
status=0
for h in offsetmap/evaluation.hpp offsetmap/oracle.hpp offsetmap/material_table.hpp \
         offsetmap/renderer/frame.hpp; do
    if out=$(echo "#include \"$h\"" | "$cxx" "${flags[@]}" - 2>&1); then
        echo "the core's include directories hold $h"; status=1
    elif ! grep -q "$h: No such file" <<<"$out"; then
        echo "$h: not the missing-header error:"; echo "$out"; status=1
    fi
done
[ $status = 0 ] && echo "the core sees offsetmap/offsetmap.hpp and no lab or renderer header"
exit $status
