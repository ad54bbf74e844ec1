#!/usr/bin/python3
"""Temporal stability from `offsetmap temporal` (temporal.csv).

    /usr/bin/python3 tools/bench/plot_temporal.py temporal.csv OUT.png

Left: per method, the mean frame-to-frame uv' change minus exact's change (texels) along the
camera path; right: its mean over the path and the share of pixels that pop (off by > 1 texel).
Needs Debian's python3-matplotlib.
"""
import csv
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rows = list(csv.DictReader(open(sys.argv[1])))
    # exact is the reference: its change minus itself is 0 by definition.
    methods = [m for m in OrderedDict.fromkeys(r["method"] for r in rows) if m != "exact"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(14, 5), gridspec_kw={"width_ratios": [3, 2]})
    colours = plt.get_cmap("tab10")
    means, pops = [], []
    for i, m in enumerate(methods):
        rs = [r for r in rows if r["method"] == m]
        left.plot([int(r["frame"]) for r in rs], [max(float(r["mean"]), 1e-5) for r in rs], "-o",
                  markersize=3, color=colours(i % 10), label=m)
        means.append(sum(float(r["mean"]) for r in rs) / len(rs))
        pops.append(100 * sum(float(r["pop_share"]) for r in rs) / len(rs))
    left.set_yscale("log")
    left.set_xlabel("frame pair (f, f+1)")
    left.set_ylabel("mean |d uv' - d uv'_exact| (texels)")
    left.set_title("Frame-to-frame error along the camera path")
    left.grid(True, which="both", alpha=0.25)
    left.legend(fontsize=7, ncol=2)
    y = range(len(methods))
    right.barh(y, means, color=[colours(i % 10) for i in y])
    right.set_xscale("log")
    right.set_yticks(list(y))
    right.set_yticklabels(["%s  (%.1f%% pop)" % (m, p) for m, p in zip(methods, pops)], fontsize=8)
    right.invert_yaxis()
    right.set_xlabel("mean over the path (texels)")
    right.set_title("Swimming and popping per method")
    right.grid(True, axis="x", which="both", alpha=0.25)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=100)
    print("wrote " + sys.argv[2])


if __name__ == "__main__":
    main()
