#!/usr/bin/python3
"""Failure maps from `offsetmap failure-map` (failure.csv).

    /usr/bin/python3 tools/bench/plot_failure.py failure.csv OUT.png [title]

One panel per method: mean uv error against exact (texels, log colour scale shared by all panels)
over view elevation (rows, 90 degrees at the top down to grazing) and depth scale (columns). The
white contour is the one-texel line: below and right of it the method lands on the wrong surface.
Needs Debian's python3-matplotlib.
"""
import csv
import math
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as colors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    rows = list(csv.DictReader(open(sys.argv[1])))
    title = sys.argv[3] if len(sys.argv) > 3 else "Failure maps"
    methods = list(OrderedDict.fromkeys(r["method"] for r in rows))
    elevs = sorted(set(float(r["elevation_deg"]) for r in rows), reverse=True)
    scales = sorted(set(float(r["scale"]) for r in rows))
    grid = {m: [[float("nan")] * len(scales) for _ in elevs] for m in methods}
    for r in rows:
        grid[r["method"]][elevs.index(float(r["elevation_deg"]))][scales.index(float(r["scale"]))] = \
            max(float(r["uv_mean"]), 1e-3)
    cols = min(5, len(methods))
    nrows = (len(methods) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(3.2 * cols + 1.2, 3.6 * nrows), squeeze=False,
                             constrained_layout=True)
    norm = colors.LogNorm(vmin=1e-3, vmax=64)
    image = None
    for ax, m in zip(axes.flat, methods):
        image = ax.imshow(grid[m], norm=norm, cmap="inferno", aspect="auto", interpolation="nearest")
        logs = [[math.log10(v) for v in row] for row in grid[m]]
        flat = [v for row in logs for v in row if not math.isnan(v)]
        if flat and min(flat) < 0.0 < max(flat):  # the 1-texel line exists in this panel
            ax.contour(logs, levels=[0.0], colors="white", linewidths=1)
        ax.set_title(m, fontsize=10)
        ax.set_xticks(range(len(scales)))
        ax.set_xticklabels(["%g" % s for s in scales], rotation=60, fontsize=7)
        ax.set_yticks(range(len(elevs)))
        ax.set_yticklabels(["%g" % e for e in elevs], fontsize=7)
        ax.set_xlabel("depth scale s", fontsize=8)
        ax.set_ylabel("view elevation (deg)", fontsize=8)
    for ax in list(axes.flat)[len(methods):]:
        ax.axis("off")
    fig.suptitle(title + " (mean uv error in texels; white line: 1 texel)", fontsize=11)
    fig.colorbar(image, ax=axes.ravel().tolist(), shrink=0.9, label="mean uv error (texels)")
    fig.savefig(sys.argv[2], dpi=95)
    print("wrote " + sys.argv[2])


if __name__ == "__main__":
    main()
