#!/usr/bin/env python3
"""Mutation check: every planted bug in mutants.ini must be caught by the tests it names.

    tests/mutants/run.py [--build build/release] [--only NAME ...] [--jobs N] [--table FILE]

Kernel and GLSL mutants are applied to a copy of kernels/ or renderer/shaders/ that the test
binary loads through OFFSETMAP_KERNEL_DIR or OFFSETMAP_SHADER_DIR (no rebuild; they run side by
side); host mutants are applied in place, the test binary rebuilt, and the source restored (and
rebuilt) afterwards, whatever happens (after a build of the same tree running beside them,
OFFSETMAP_MUTANTS_AFTER=PID, has ended); each one's tests run on a copy of its binary beside the
next one's build. Host mutants of one file run one after the other, so a
file is compiled once a mutant and once restored, not restored between its own. A mutant is killed when one
of its tests fails; it survives when they all pass. A mutant whose `find` text does not occur
exactly once, whose kernel does not build, or whose host source does not compile is stale: the
list must be mended. A mutant with `cpu = FLAG` plants its bug in code compiled only where the
CPU has that flag (/proc/cpuinfo): elsewhere it is reported n/a, neither killed nor failed.
Exit status 1 when any mutant survives or is stale. Standard library only.
"""
import argparse
import configparser
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TIMEOUT_S = 600


def load(path):
    cp = configparser.ConfigParser(interpolation=None, delimiters=("=",))
    cp.optionxform = str
    with open(path) as f:
        cp.read_file(f)
    mutants = []
    for name in cp.sections():
        m = dict(cp[name])
        missing = {"file", "find", "replace", "tests", "why"} - set(m)
        if missing:
            sys.exit(f"mutants.ini [{name}]: missing {', '.join(sorted(missing))}")
        m["name"] = name
        mutants.append(m)
    return mutants


def cpu_flags():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("flags"):
                    return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return set()


def mutate(text, m):
    count = text.count(m["find"])
    if count != 1:
        return None, f"'find' occurs {count} times in {m['file']}"
    return text.replace(m["find"], m["replace"]), None


# Sources a test binary reads at run time from a folder an environment variable names.
FOLDERS = {"kernels/": "OFFSETMAP_KERNEL_DIR", "renderer/shaders/": "OFFSETMAP_SHADER_DIR"}


def folder_of(m):
    return next((f for f in FOLDERS if m["file"].startswith(f)), None)


def run_tests(build, m, folder_env=None, binary=None):
    # Figures a mutated build measures must not reach the figure check's folder.
    env = dict(os.environ, OFFSETMAP_TEST_DATA=os.path.join(ROOT, "data"),
               OFFSETMAP_FIGURES=os.path.join(tempfile.gettempdir(), "om_mutant_figures"))
    for var in FOLDERS.values():
        env.pop(var, None)
    env.update(kv.split("=", 1) for kv in m.get("env", "").split())
    if folder_env:
        env.update(folder_env)
    # One failing test kills the mutant: the rest of its tests need not run.
    cmd = [binary or os.path.join(build, "tests", "offsetmap_tests"),
           "--gtest_filter=" + m["tests"], "--gtest_fail_fast"]
    try:
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return "killed", "timed out (a hang counts as caught)"
    out = p.stdout + p.stderr
    if "kernel build failed" in out:
        return "stale", "the mutated kernel does not build"
    if p.returncode < 0:  # a crash (a signal) is a failing test too
        return "killed", f"test binary died of signal {-p.returncode}"
    ran = re.search(r"\[==========\] (\d+) tests? from", out)
    if not ran or int(ran.group(1)) == 0:
        return "stale", f"no test matches '{m['tests']}'"
    failed = sorted(set(re.findall(r"^\[  FAILED  \] (\S+)", out, re.M)) - {"1", "TEST,"})
    failed = [f for f in failed if "." in f]
    if p.returncode != 0 and failed:
        return "killed", ", ".join(failed)
    if p.returncode != 0:
        return "killed", f"test binary exited {p.returncode}"
    return "survived", "every named test passed"


def folder_mutant(build, m):
    folder = folder_of(m)
    with tempfile.TemporaryDirectory(prefix="om_mutant_") as tmp:
        copy = os.path.join(tmp, folder)
        shutil.copytree(os.path.join(ROOT, folder), copy)
        target = os.path.join(tmp, m["file"])
        with open(target) as f:
            text, err = mutate(f.read(), m)
        if err:
            return "stale", err
        with open(target, "w") as f:
            f.write(text)
        return run_tests(build, m, {FOLDERS[folder]: copy})


def build_tests(build):
    p = subprocess.run(["cmake", "--build", build, "--target", "offsetmap_tests", "-j",
                        str(os.cpu_count() or 2)], capture_output=True, text=True)
    return p.returncode == 0, p.stdout + p.stderr


def host_mutant_build(build, m, tmp):
    """The mutant applied, the test binary built and copied aside, the source restored: returns
    (None, copy) to run, or (verdict, detail) when it is stale. Its tests run on the copy while
    the next mutant builds (their binaries' paths to data and the CLI are absolute)."""
    path = os.path.join(ROOT, m["file"])
    with open(path) as f:
        original = f.read()
    text, err = mutate(original, m)
    if err:
        return "stale", err
    try:
        with open(path, "w") as f:
            f.write(text)
        ok, log = build_tests(build)
        if not ok:
            return "stale", "the mutated source does not compile"
        copy = os.path.join(tmp, m["name"])
        shutil.copy2(os.path.join(build, "tests", "offsetmap_tests"), copy)
        return None, copy
    finally:
        with open(path, "w") as f:
            f.write(original)


def host_mutant_test(build, m, copy):
    try:
        return run_tests(build, m, binary=copy)
    finally:
        os.remove(copy)


def wait_for_build_beside():
    """Host mutants edit the sources in place, so a build of the same tree running beside this
    check (CI's sanitizer build, its pid in OFFSETMAP_MUTANTS_AFTER) must be done before they
    start, or it compiles a mutated file. Done: gone, or a zombie its parent has not reaped."""
    pid = os.environ.get("OFFSETMAP_MUTANTS_AFTER")
    if not pid:
        return
    print(f"mutants: the host mutants wait for process {pid} (a build of this tree) to end",
          flush=True)
    while True:
        try:
            with open(f"/proc/{int(pid)}/stat") as f:
                state = f.read().rsplit(")", 1)[1].split()[0]
        except (OSError, ValueError, IndexError):
            return
        if state in ("Z", "X"):
            return
        time.sleep(2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--only", nargs="*", help="mutant names")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--table", help="also write the result table (markdown) here")
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    mutants = load(os.path.join(os.path.dirname(os.path.abspath(__file__)), "mutants.ini"))
    if args.only:
        unknown = set(args.only) - {m["name"] for m in mutants}
        if unknown:
            sys.exit(f"unknown mutants: {', '.join(sorted(unknown))}")
        mutants = [m for m in mutants if m["name"] in args.only]
    # A host mutant edits the tree in place: restore it on Ctrl-C or a kill too.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))

    results = {}
    start = time.time()

    def report(m, verdict, detail, t0):
        results[m["name"]] = (verdict, detail, time.time() - t0)
        print(f"  {verdict:8} {m['name']:34} {time.time() - t0:4.0f} s  {detail}", flush=True)

    def one(m):  # a folder mutant (they run side by side; host mutants edit the tree, in turn)
        t0 = time.time()
        report(m, *folder_mutant(build, m), t0)

    flags = cpu_flags()
    for m in [m for m in mutants if m.get("cpu") and m["cpu"] not in flags]:
        report(m, "n/a", f"this CPU lacks {m['cpu']}: the mutated code is not compiled here",
               time.time())
    mutants = [m for m in mutants if m["name"] not in results]
    folders = [m for m in mutants if folder_of(m)]
    # Grouped by file (in the order each file first appears), the groups in turn.
    hosts = sorted((m for m in mutants if not folder_of(m)),
                   key=lambda m: [x["file"] for x in mutants].index(m["file"]))
    print(f"mutants: {len(folders)} kernel and GLSL (a folder copy), {len(hosts)} host (rebuilt)")
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        list(pool.map(one, folders))
    if hosts:
        wait_for_build_beside()
    try:
        # Each mutant's tests run beside the next one's build (one at a time), on its own copy of
        # the test binary.
        with tempfile.TemporaryDirectory(prefix="om_host_mutants_") as tmp, \
                ThreadPoolExecutor(max_workers=1) as tests:
            pending = []
            for m in hosts:
                t0 = time.time()
                verdict, detail = host_mutant_build(build, m, tmp)
                if verdict:
                    report(m, verdict, detail, t0)
                    continue
                pending.append(tests.submit(
                    lambda m=m, copy=detail, t0=t0: report(m, *host_mutant_test(build, m, copy),
                                                           t0)))
            for f in pending:
                f.result()
    finally:
        if hosts:
            ok, log = build_tests(build)  # the restored sources
            if not ok:
                print(log)
                sys.exit("mutants: the restored tree does not build")

    rows = ["| mutant | file | the bug | killed by |", "|---|---|---|---|"]
    for m in load(os.path.join(os.path.dirname(os.path.abspath(__file__)), "mutants.ini")):
        if m["name"] not in results:
            continue
        verdict, detail, _ = results[m["name"]]
        by = detail if verdict == "killed" else f"**{verdict.upper()}**: {detail}"
        rows.append(f"| {m['name']} | {m['file']} | {m['why']} | {by} |")
    if args.table:
        with open(args.table, "w") as f:
            f.write("\n".join(rows) + "\n")
    bad = [n for n, (v, _, _) in results.items() if v not in ("killed", "n/a")]
    na = [n for n, (v, _, _) in results.items() if v == "n/a"]
    applied = len(results) - len(na)
    print(f"mutants: {applied - len(bad)} of {applied} killed in {time.time() - start:.0f} s" +
          (f" ({len(na)} n/a on this CPU: {', '.join(na)})" if na else "") +
          (f"; not killed: {', '.join(bad)}" if bad else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
