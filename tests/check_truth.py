#!/usr/bin/python3
"""check_truth.py FRAME_JSON [MODES]: `offsetmap frame --truth --forward`'s truth section, by content.

The keys the tools read, every frame mode measured (MODES, comma-separated: deferred and forward
unless given), the tessellation rows from the coarsest lattice to the finest with their error
falling toward the truth, the truth's bound finite and below the deferred frame's p95 error, and
the per-pixel methods. With deferred-two-layers among the modes: its silhouette band mismatch at
most the curved frame's, which is below the tangent plane's, and the forward frame's coverage
(without a pre-pass it shows what the second layer shows) the two-layer frame's. Where a mode has
triplanar rows: both, and the pixels one projection covers (the ray over the surface, the relief's
own model there) closer to the truth at p95 than the blends (which merge three traces)."""
import json
import math
import sys


def fail(why):
    sys.exit("check_truth: " + why)


def main():
    doc = json.load(open(sys.argv[1]))
    t = doc.get("truth") or fail("no truth section")
    for key in ("bound_texels", "modes", "tessellation", "texels_per_quad", "triangles", "bytes",
                "notes"):
        if key not in t:
            fail("truth has no '%s'" % key)
    modes = {m["mode"]: m for m in t["modes"]}
    # null where no pixel compared has a bound: only triplanar relief, which has none
    bound = t["bound_texels"]
    if bound is None:
        if not any("one_projection" in m for m in modes.values()):
            fail("bound_texels is null in a frame without triplanar relief")
    elif not (math.isfinite(bound) and bound >= 0):
        fail("bound_texels is %r" % bound)
    wanted = sys.argv[2].split(",") if len(sys.argv) > 2 else ["deferred", "forward"]
    for name in wanted:
        m = modes.get(name) or fail("no mode '%s' in %s" % (name, sorted(modes)))
        if m["compared_pixels"] <= 0:
            fail("%s compared no pixels" % name)
        for key in ("mean", "p95", "max"):
            if not math.isfinite(m["uv_err_texels"][key]) or not math.isfinite(m["depth_err"][key]):
                fail("%s: %s is not finite" % (name, key))
        ids = [e["id"] for e in m.get("materials", [])]
        if not ids or any(e["interior_pixels"] < 0 for e in m["materials"]):
            fail("%s: per-material rows %s" % (name, ids))
        c = m["coverage_mismatch"]
        if c["pixels"] != c["silhouette_band"] + c["interior"]:
            fail("%s: mismatch %d is not band %d + interior %d" % (
                name, c["pixels"], c["silhouette_band"], c["interior"]))
    rows = t["tessellation"]
    lattices = [r["texels_per_quad"] for r in rows]
    if lattices[:4] != [8, 4, 2, 1]:
        fail("tessellation lattices %s" % lattices)
    for r in rows:
        for key in ("triangles", "raster_ms", "bytes", "uv_err_texels", "coverage_mismatch"):
            if key not in r:
                fail("tessellation row without '%s'" % key)
    p95 = [r["uv_err_texels"]["p95"] for r in rows]
    if not all(a >= b for a, b in zip(p95, p95[1:])):
        fail("tessellation error does not fall with the lattice: %s" % p95)
    tris = [r["triangles"] for r in rows]
    if not all(a < b for a, b in zip(tris, tris[1:])):
        fail("triangles do not grow with the lattice: %s" % tris)
    if bound is not None and bound >= modes["deferred"]["uv_err_texels"]["p95"]:
        fail("the truth's bound %.3g is not below the deferred frame's p95 %.3g" % (
            bound, modes["deferred"]["uv_err_texels"]["p95"]))
    if "deferred-two-layers" in wanted:
        band = {m: modes[m]["coverage_mismatch"]["silhouette_band"]
                for m in ("deferred", "deferred-curved", "deferred-two-layers", "forward")}
        if not band["deferred-two-layers"] <= band["deferred-curved"] < band["deferred"]:
            fail("silhouette band mismatch does not fall to the two layers: %s" % band)
        if band["forward"] != band["deferred-two-layers"]:
            fail("forward and the two-layer frame show other pixels: %s" % band)
    for name in wanted:
        m = modes[name]
        if "one_projection" not in m and "blend" not in m:
            continue
        one, blend = m.get("one_projection"), m.get("blend")
        if not one or not blend or one["pixels"] <= 0 or blend["pixels"] <= 0:
            fail("%s: triplanar rows %r, %r" % (name, one, blend))
        if not one["uv_err_texels"]["p95"] < blend["uv_err_texels"]["p95"]:
            fail("%s: one projection's p95 %.3g is not below the blend's %.3g" % (
                name, one["uv_err_texels"]["p95"], blend["uv_err_texels"]["p95"]))
    methods = [m["method"] for m in t["pixel_methods"]]
    if "exact" not in methods or "none" not in methods:
        fail("pixel methods %s" % methods)
    print("check_truth: %d modes, %d lattices, bound %s texels, deferred p95 %.3g" % (
        len(modes), len(rows), "none" if bound is None else "%.3g" % bound,
        modes["deferred"]["uv_err_texels"]["p95"]))


if __name__ == "__main__":
    main()
