#!/usr/bin/env bash
# check.sh install SRC BUILD : install offsetmap from its build tree BUILD into a temporary
#                        prefix, then build and run tests/package against it with
#                        find_package(offsetmap CONFIG) (subdir below builds the library alone
#                        afresh, so this one need not build it a second time)
# check.sh subdir SRC  : build tests/package with add_subdirectory(SRC): the library alone is
#                        built (no CLI, bench or tests, no OpenImageIO), and runs
set -euo pipefail
mode=$1 src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
jobs=$(nproc)
quiet() { "$@" >"$tmp/log" 2>&1 || { cat "$tmp/log"; exit 1; }; }
case $mode in
install)
    quiet cmake --install "$3" --prefix "$tmp/prefix"
    for f in include/offsetmap/offsetmap.hpp include/offsetmap/evaluation.hpp include/offsetmap/shared.h \
             lib/cmake/offsetmap/offsetmapConfig.cmake; do
        [ -f "$tmp/prefix/$f" ] || { echo "not installed: $f"; exit 1; }
    done
    # Only what it installs: the renderer library is not, so neither are its headers.
    [ ! -e "$tmp/prefix/include/offsetmap/renderer" ] ||
        { echo "the renderer's headers were installed without the renderer"; exit 1; }
    quiet cmake -S "$src/tests/package" -B "$tmp/consumer" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$tmp/prefix"
    quiet cmake --build "$tmp/consumer" -j "$jobs"
    # The installed library needs no source tree: the checkout is out of reach while it runs.
    (cd / && "$tmp/consumer/consumer" && "$tmp/consumer/consumer_evaluation" &&
        "$tmp/consumer/engine_example" && "$tmp/consumer/engine_frame_example")
    ;;
subdir)
    quiet cmake -S "$src/tests/package" -B "$tmp/consumer" -DCMAKE_BUILD_TYPE=Release \
        -DOFFSETMAP_SOURCE="$src"
    quiet cmake --build "$tmp/consumer" -j "$jobs"
    [ ! -e "$tmp/consumer/offsetmap/offsetmap" ] || { echo "the CLI was built"; exit 1; }
    [ ! -e "$tmp/consumer/consumer_evaluation" ] || { echo "the evaluation library was built"; exit 1; }
    (cd / && "$tmp/consumer/consumer" && "$tmp/consumer/engine_example" &&
        "$tmp/consumer/engine_frame_example")
    ;;
esac
# Neither binary of the pass links OpenImageIO.
for exe in consumer engine_example; do
    libs=$(ldd "$tmp/consumer/$exe")  # whole, then read: no early-exit reader behind pipefail
    ! grep -qi openimageio <<<"$libs" || { echo "$exe links OpenImageIO"; exit 1; }
done
echo "package ($mode): ok"
