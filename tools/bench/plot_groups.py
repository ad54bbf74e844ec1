#!/usr/bin/python3
"""SIMD-group charts from `offsetmap_bench --groups` (bench-groups.json).

    /usr/bin/python3 tools/bench/plot_groups.py bench-groups.json OUT_DIR

Writes OUT_DIR/bench-groups.png: per scene (room, terrain, random rays) each method's p95 uv error
against exact over its cost twice: the lane-steps a pixel costs in SIMD groups of 32 neighbouring
pixels (8 x 4; a group runs as long as its slowest pixel: the part of a GPU's cost a CPU run
hides) and the time per pixel on the device the bench ran on. Exact methods (error 0) sit on the
bottom line. Needs Debian's python3-matplotlib.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-3  # texels: where an exact method's error is drawn on the log axis


def label(row):
    return row["method"] + ("" if row["setting"] == "defaults" else " " + row["setting"])


def plot_groups(doc, out_dir):
    groups = doc["groups"]
    order = ["room", "terrain", "random"]
    scenes = sorted([(name, rows) for name, rows in groups["scenes"].items()
                     if isinstance(rows, list)],
                    key=lambda s: order.index(s[0]) if s[0] in order else len(order))
    fig, axes = plt.subplots(2, len(scenes), figsize=(6.2 * len(scenes), 9), squeeze=False)
    for col, (name, rows) in enumerate(scenes):
        for row_i, (key, xlabel) in enumerate([
                ("group32", "lane-steps per traced pixel, groups of 32 (8 x 4)"),
                ("ns_per_pixel", "ns per pixel, %s" % doc["device"].split("/")[-1].strip())]):
            ax = axes[row_i][col]
            exact_seen = 0  # the exact methods share the bottom line: their labels are stacked
            for r in rows:
                x = r["group_steps_per_pixel"]["32"] if key == "group32" else r["ns_per_pixel"]
                if x <= 0:
                    continue
                y = max(r["error_p95"], FLOOR)
                marker = "s" if r["error_p95"] < 0.01 else "o"
                ax.plot([x], [y], marker, ms=6)
                lift = 2
                if r["error_p95"] < 0.01:
                    lift = 4 + 11 * exact_seen
                    exact_seen += 1
                ax.annotate(label(r) + ("  e%.2f" % r["efficiency"]["32"] if key == "group32"
                                        else ""), (x, y), fontsize=6.5, xytext=(3, lift),
                            textcoords="offset points",
                            arrowprops=dict(arrowstyle="-", lw=0.4, alpha=0.5)
                            if lift > 4 else None)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel(xlabel, fontsize=8)
            ax.set_ylabel("p95 uv error against exact (texels; exact at %g)" % FLOOR, fontsize=8)
            ax.set_title("%s, %dx%d" % (name, *groups["resolution"]), fontsize=10)
            ax.grid(True, which="both", alpha=0.25)
    fig.suptitle("error against cost: in SIMD groups of 32 (top; e = group efficiency) and on "
                 "this device (bottom)", fontsize=11)
    fig.tight_layout()
    fig.savefig(out_dir + "/bench-groups.png", dpi=90)
    print("wrote %s/bench-groups.png" % out_dir)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    plot_groups(json.load(open(sys.argv[1])), sys.argv[2])


if __name__ == "__main__":
    main()
