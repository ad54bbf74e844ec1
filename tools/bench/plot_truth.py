#!/usr/bin/python3
"""Pixel methods against tessellation, both measured against the displaced mesh (`offsetmap frame
--truth`, frame.json's truth section).

    /usr/bin/python3 tools/bench/plot_truth.py frame.json OUT.png

Left: uv error against the truth (p95, texels) against the cost of a pixel's uv': for the
per-pixel methods the G-buffer draw of the base meshes plus the offset pass, for tessellation the
G-buffer draw of the displaced mesh at each lattice; the Pareto front dashed. Right: the pixels
whose coverage differs from the truth's (relief shown in one, something else in the other).
Both costs are wall-clock on the machine that rendered the frame (named in the title).
Needs Debian's python3-matplotlib.
"""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-3  # errors drawn at no less than this on the log axis


def pareto(points):
    front, best = [], float("inf")
    for p in sorted(points, key=lambda q: (q[0], q[1])):
        if p[1] < best:
            front.append(p)
            best = p[1]
    return front


def label_methods(fig, axes, points):
    """Methods of about the same cost and error crowd each other: each label takes the first of a
    few places beside its point where it overlaps no label placed before it."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    taken = []
    places = [(5, 4), (5, -11), (5, 12), (5, -20), (-5, 4), (-5, -11)]
    for x, y, name, _ in sorted(points, key=lambda p: (p[1], p[0])):
        for dx, dy in places:
            label = axes.annotate(name, (x, y), textcoords="offset points", xytext=(dx, dy),
                                  fontsize=8, ha="left" if dx > 0 else "right")
            box = label.get_window_extent(renderer).expanded(1.05, 1.1)
            if not any(box.overlaps(t) for t in taken) or (dx, dy) == places[-1]:
                taken.append(box)
                break
            label.remove()


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    doc = json.load(open(sys.argv[1]))
    truth = doc["truth"]
    pixel = [(m["gbuffer_ms"] + m["offset_ms"], max(m["uv_err_texels"]["p95"], FLOOR),
              m["method"], m["coverage_mismatch"]["pixels"]) for m in truth["pixel_methods"]]
    # The truth's own lattice is the reference itself (no error by definition): drawn, not ranked.
    own = truth["texels_per_quad"]
    tess = [(t["raster_ms"], max(t["uv_err_texels"]["p95"], FLOOR),
             "tess %g" % t["texels_per_quad"] + (" (the truth)" if t["texels_per_quad"] == own
                                                  else ""),
             t["coverage_mismatch"]["pixels"]) for t in truth["tessellation"]]
    fig, (left, right) = plt.subplots(1, 2, figsize=(14, 5.5), gridspec_kw={"width_ratios": [3, 2]})
    left.scatter([p[0] for p in pixel], [p[1] for p in pixel], color="tab:blue", zorder=3,
                 label="per-pixel method (base G-buffer + offset pass)")
    left.plot([p[0] for p in tess], [p[1] for p in tess], "-s", color="tab:orange", zorder=3,
              label="tessellated displacement (G-buffer of the displaced mesh)")
    for x, y, name, _ in tess:
        left.annotate(name, (x, y), textcoords="offset points", xytext=(5, 4), fontsize=8)
    front = pareto([(p[0], p[1]) for p in pixel + tess if "(the truth)" not in p[2]])
    left.step([p[0] for p in front], [p[1] for p in front], where="post", color="black",
              linestyle="--", linewidth=1, label="Pareto front")
    left.set_xscale("log")
    left.set_yscale("log")
    left.set_xlabel("ms per frame for uv' (wall clock)")
    left.set_ylabel("uv error against the displaced mesh, p95 (texels; %g drawn as floor)" % FLOOR)
    left.set_title("%s %dx%d: raster on %s, passes on %s (this machine's CPU)" % (
        doc["scene"], doc["width"], doc["height"], truth["raster_on"].split(" (")[0],
        truth["passes_on"].split(" / ")[0]), fontsize=9)
    left.grid(True, which="both", alpha=0.25)
    left.legend(fontsize=8)
    names = [p[2] for p in pixel + tess]
    right.barh(range(len(names)), [p[3] for p in pixel + tess],
               color=["tab:blue"] * len(pixel) + ["tab:orange"] * len(tess))
    right.set_yticks(range(len(names)))
    right.set_yticklabels(names, fontsize=8)
    right.invert_yaxis()
    right.set_xlabel("pixels whose coverage differs from the truth")
    right.set_title("Coverage mismatch (silhouettes, tile edges)", fontsize=9)
    fig.tight_layout()
    label_methods(fig, left, pixel)
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
