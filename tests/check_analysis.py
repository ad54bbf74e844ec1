"""Checks what `sweep`, `failure-map` and `temporal` wrote (cli_check.sh analysis), by content:
the measurements must say what the methods are, not only exist. Run with /usr/bin/python3
(Debian's python3-matplotlib reads the PNGs).

    check_analysis.py DIR   (DIR holds s/ f/ t/ as cli_check.sh writes them)
"""
import csv
import json
import math
import sys

import matplotlib.image as mpimg

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def params(setting):
    return dict(kv.split("=") for kv in setting.split()) if setting != "defaults" else {}


def check_png(path, min_w, min_h):
    img = mpimg.imread(path)
    h, w = img.shape[:2]
    check(w >= min_w and h >= min_h, f"{path}: {w}x{h}, expected at least {min_w}x{min_h}")
    rgb = img[..., :3]
    check(float(rgb.std()) > 0.01, f"{path}: a blank image")


def check_sweep(d):
    recs = rows(f"{d}/sweep.csv")
    # parallax, exact (defaults) and pom's eight settings of its registry grid, on two view sets.
    check(len(recs) == 20, f"sweep.csv: {len(recs)} rows, expected 20")
    with open(f"{d}/sweep.json") as f:
        js = json.load(f)["records"]
    check(len(js) == len(recs), "sweep.json and sweep.csv hold different records")
    for r, j in zip(recs, js):
        for key in ("uv_mean", "fetches_mean", "ns_per_pixel"):
            check(math.isclose(float(r[key]), j[key], rel_tol=1e-5, abs_tol=1e-9),
                  f"sweep.json {key} {j[key]} != csv {r[key]} ({r['method']} {r['setting']})")
    for views in ("camera", "random"):
        sel = [r for r in recs if r["views"] == views]
        by = {(r["method"], r["setting"]): r for r in sel}
        exact = by[("exact", "defaults")]
        # exact is the reference: no error against itself, and it walks at least one cell.
        for key in ("uv_mean", "uv_p95", "uv_max", "wrong_share", "depth_error"):
            check(float(exact[key]) == 0.0, f"{views}: exact {key} = {exact[key]}, expected 0")
        check(float(exact["fetches_mean"]) >= 1.0, f"{views}: exact reads no patch")
        par = by[("parallax", "defaults")]
        check(float(par["fetches_mean"]) == 1.0 and float(par["fetches_max"]) == 1.0,
              f"{views}: parallax must read exactly one height")
        poms = [r for r in sel if r["method"] == "pom"]
        check(len(poms) == 8, f"{views}: {len(poms)} pom settings, expected 8")
        for r in poms:
            p = params(r["setting"])
            cap = max(int(p["min_samples"]), int(p["max_samples"])) + 1
            check(float(r["fetches_max"]) <= cap,
                  f"{views}: pom {r['setting']} read {r['fetches_max']} > {cap} heights")
            # Every pom setting beats parallax on this noise map.
            check(float(r["uv_mean"]) < float(par["uv_mean"]),
                  f"{views}: pom {r['setting']} no better than parallax")
        # Tatarchuk's rule (no spacing): more samples, lower error.
        lerps = sorted((r for r in poms if "spacing" not in params(r["setting"])),
                       key=lambda r: (int(params(r["setting"])["max_samples"]),
                                      int(params(r["setting"])["min_samples"])))
        check(len(lerps) == 7, f"{views}: {len(lerps)} pom settings by V.z, expected 7")
        prev = float(par["uv_mean"])
        for r in lerps:
            check(float(r["uv_mean"]) < prev, f"{views}: pom {r['setting']} error did not fall")
            prev = float(r["uv_mean"])
        for r in sel:
            ns = float(r["ns_per_pixel"])
            check(math.isfinite(ns) and ns > 0, f"{views}: {r['method']} time {ns}")
    for name in ("pareto-ns.png", "pareto-fetches.png", "pareto-by-map.png", "pareto-cheap.png"):
        check_png(f"{d}/{name}", 300, 300)


def check_failure(d):
    recs = rows(f"{d}/failure.csv")
    methods = {r["method"] for r in recs}
    check(methods == {"parallax", "exact"}, f"failure.csv methods {methods}")
    elevs = sorted({float(r["elevation_deg"]) for r in recs})
    scales = sorted({float(r["scale"]) for r in recs})
    check(len(recs) == len(methods) * len(elevs) * len(scales),
          "failure.csv: the elevation x scale grid is incomplete")
    check(elevs[-1] == 90 and elevs[0] <= 1.0, f"failure.csv elevations {elevs}")
    for r in recs:
        if r["method"] == "exact":
            check(float(r["uv_mean"]) == 0.0, f"exact off itself at {r['elevation_deg']} deg")
    par = {(float(r["elevation_deg"]), float(r["scale"])): float(r["uv_mean"])
           for r in recs if r["method"] == "parallax"}
    for s in scales:
        # Straight down parallax is exact (no horizontal travel); toward grazing it fails.
        check(par[(90.0, s)] == 0.0, f"parallax at 90 deg, s={s}: {par[(90.0, s)]}")
        check(par[(elevs[0], s)] > par[(elevs[-2], s)],
              f"parallax error does not grow toward grazing at s={s}")
    check_png(f"{d}/failure-map.png", 400, 200)


def check_temporal(d, frames):
    recs = rows(f"{d}/temporal.csv")
    by = {}
    for r in recs:
        by.setdefault(r["method"], []).append(r)
    check(set(by) == {"none", "pom", "exact"}, f"temporal.csv methods {set(by)}")
    for m, rs in by.items():
        check(len(rs) == frames - 1, f"temporal {m}: {len(rs)} frame pairs, expected {frames - 1}")
    check(all(float(r["mean"]) == 0.0 for r in by["exact"]), "exact swims against itself")
    none = sum(float(r["mean"]) for r in by["none"])
    pom = sum(float(r["mean"]) for r in by["pom"])
    check(pom < none, f"pom ({pom}) swims more than no offset ({none})")
    check_png(f"{d}/temporal.png", 400, 200)


def main():
    d = sys.argv[1]
    check_sweep(f"{d}/s")
    check_failure(f"{d}/f")
    check_temporal(f"{d}/t", int(sys.argv[2]))
    for f in failures:
        print("check_analysis:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
