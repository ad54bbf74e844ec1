#!/usr/bin/env bash
# Runs every libFuzzer harness of build/fuzz for SECONDS each (default 60), as many at once as the
# machine has cores, from the repository's corpus (tests/fuzz/corpus/<target>, read only) into a
# working corpus under OUT (default out/fuzz). Prints each one's executions and what it found;
# exits 1 when any found something: a finding, crash, sanitizer report, leak, hang (a run over
# 60 s: the first engine-form input also builds its PoCL program) or allocation above 256 MiB
# (the readers' limit in the harnesses is 64 MiB). The input that caused it is
# OUT/<target>/crash-* (or leak-, timeout-, oom-): fix the reader, then add the input to the
# corpus as found-<what> so that the suite replays it (FuzzCorpus.*).
# OFFSETMAP_FUZZ_SEED fixes libFuzzer's seed (default: a random one); how far a seeded run gets
# in its seconds depends on the machine, so a finding in CI's minute may come later here: its input
# is printed below (base64) with the report, which reaches the log even from a decoder's call
# (-close_fd_mask=2 keeps libFuzzer's own stream; the harness keeps the sanitizers').
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-60}
out=${2:-out/fuzz}
bin=build/fuzz/tests/fuzz
mkdir -p "$out"
targets=()
for f in "$bin"/fuzz_*; do targets+=("$(basename "$f" | sed 's/^fuzz_//')"); done
[ ${#targets[@]} -gt 0 ] || { echo "fuzz: no harnesses in $bin" >&2; exit 1; }
one() {
    local t=$1 seconds=$2 out=$3 bin=$4
    mkdir -p "$out/$t/corpus"
    # PoCL alone (Mesa's ICDs keep load-time allocations LeakSanitizer reports).
    OCL_ICD_VENDORS=/etc/OpenCL/vendors/pocl.icd \
    ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0:detect_stack_use_after_return=0 \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    LSAN_OPTIONS=suppressions=tests/sanitize/lsan.supp:print_suppressions=0 \
        "$bin/fuzz_$t" -seed="${OFFSETMAP_FUZZ_SEED:-0}" -max_total_time="$seconds" -timeout=60 -malloc_limit_mb=256 \
        -rss_limit_mb=4096 -print_final_stats=1 -close_fd_mask=2 -report_slow_units=60 \
        -artifact_prefix="$out/$t/" \
        "$out/$t/corpus" "tests/fuzz/corpus/$t" >"$out/$t.log" 2>&1
    echo $? >"$out/$t.rc"
}
export -f one
export OFFSETMAP_FUZZ_SEED
printf '%s\n' "${targets[@]}" | xargs -P "$(nproc)" -I{} bash -c "one {} $seconds $out $bin"
status=0
printf '%-16s %12s %10s %8s  %s\n' target executions exec/s corpus result
for t in "${targets[@]}"; do
    rc=$(cat "$out/$t.rc")
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/$t.log" | tail -1)
    speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$out/$t.log" | tail -1)
    units=$(find "$out/$t/corpus" -type f | wc -l)
    found=$(find "$out/$t" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o \
        -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
    result="nothing found"
    if [ "$rc" != 0 ] || [ "$found" != 0 ]; then
        result="FOUND (exit $rc): $(ls "$out/$t" | { grep -E '^(crash|leak|timeout|oom)-' || true; } | sed -n 1,3p | tr '\n' ' ')"
        status=1
    fi
    printf '%-16s %12s %10s %8s  %s\n' "$t" "${runs:-?}" "${speed:-?}" "$units" "$result"
done
if [ $status != 0 ]; then
    for t in "${targets[@]}"; do
        [ "$(cat "$out/$t.rc")" = 0 ] || { echo "== $out/$t.log"; grep -v '^#' "$out/$t.log" | tail -40; }
        # The inputs themselves, so that a finding on a machine whose files are gone can be
        # replayed: base64 -d into a file, then build/fuzz/tests/fuzz/fuzz_<target> FILE.
        for a in $(find "$out/$t" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o \
            -name 'timeout-*' -o -name 'oom-*' \) | sed -n 1,3p); do
            echo "== $a ($(stat -c %s "$a") bytes, base64)"
            head -c 65536 "$a" | base64 -w 100
        done
    done
fi
exit $status
