#!/usr/bin/env bash
# cli_check.sh fail CODE PATTERN CMD... : CMD must exit CODE (1 error, 2 usage) with exactly one
#                                         stderr line, matching PATTERN
# cli_check.sh ok PATTERN CMD...    : CMD must exit 0 with output matching PATTERN
# cli_check.sh quiet PATTERN CMD...  : as ok, and nothing on stderr
# cli_check.sh analysis PATTERN OFFSETMAP DATA  : small sweep, failure map, temporal -> CSV/JSON/PNG,
#                                                checked by content (check_analysis.py)
set -u
mode=$1
code=
if [ "$mode" = fail ]; then
    code=$2
    shift
fi
pattern=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
case $mode in
fail)
    "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    [ "$rc" -lt 128 ] || { echo "crashed with exit $rc"; cat "$tmp/err"; exit 1; }
    [ "$rc" -eq "$code" ] || { echo "expected exit $code, got $rc:"; cat "$tmp/err"; exit 1; }
    grep -Eq -e "$pattern" "$tmp/err" || { echo "stderr does not match '$pattern':"; cat "$tmp/err"; exit 1; }
    [ "$(grep -c . "$tmp/err")" -eq 1 ] || { echo "expected one stderr line:"; cat "$tmp/err"; exit 1; }
    ;;
quiet)
    "$@" >"$tmp/out" 2>"$tmp/err" || { echo "exit $?"; cat "$tmp/out" "$tmp/err"; exit 1; }
    [ ! -s "$tmp/err" ] || { echo "expected nothing on stderr:"; cat "$tmp/err"; exit 1; }
    grep -Eq -e "$pattern" <<<"$(tr "\n" " " <"$tmp/out")" || { echo "output does not match '$pattern'"; exit 1; }
    ;;
ok)
    "$@" >"$tmp/out" 2>&1 || { echo "exit $?"; cat "$tmp/out"; exit 1; }
    grep -Eq -e "$pattern" <<<"$(tr "\n" " " <"$tmp/out")" || { echo "output does not match '$pattern'"; exit 1; }
    ;;
analysis)
    om=$1 data=$2
    "$om" sweep --maps "$data/noise.png" --methods parallax pom exact --quick -o "$tmp/s" \
        >"$tmp/out" 2>&1 || { cat "$tmp/out"; exit 1; }
    "$om" failure-map --height-map "$data/bumps.png" --methods parallax exact --samples 8 \
        -o "$tmp/f" >>"$tmp/out" 2>&1 || { cat "$tmp/out"; exit 1; }
    "$om" temporal --height-map "$data/bumps.png" --methods none pom exact --frames 3 \
        -o "$tmp/t" >>"$tmp/out" 2>&1 || { cat "$tmp/out"; exit 1; }
    grep -q "warning" "$tmp/out" && { echo "a chart was not drawn:"; cat "$tmp/out"; exit 1; }
    for f in s/sweep.csv s/sweep.json s/pareto-ns.png s/pareto-fetches.png s/pareto-by-map.png s/pareto-cheap.png \
             f/failure.csv f/failure-map.png t/temporal.csv t/temporal.png; do
        [ -s "$tmp/$f" ] || { echo "missing $f"; cat "$tmp/out"; exit 1; }
    done
    # What they measured, by content (errors, fetch counts, grids, charts not blank).
    /usr/bin/python3 "$(dirname "$0")/check_analysis.py" "$tmp" 3 || { cat "$tmp/out"; exit 1; }
    grep -Eq -e "$pattern" <<<"$(tr "\n" " " <"$tmp/out")" || { echo "output does not match '$pattern'"; exit 1; }
    ;;
esac
exit 0
