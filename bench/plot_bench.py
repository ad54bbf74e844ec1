#!/usr/bin/python3
"""Cost-growth charts from `offsetmap_bench` (bench.json).

    /usr/bin/python3 bench/plot_bench.py bench.json OUT_DIR

Writes OUT_DIR/bench-growth.png: kernel ns/pixel against resolution (should be flat), against
height-map size (cache effects) and against step count (should be linear), plus the methods at
their defaults as a share of the device's fetch roofline. Needs Debian's python3-matplotlib.
"""
import json
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def series(rows, key):
    out = OrderedDict()
    for r in rows:
        out.setdefault(r["method"], []).append((r[key], r["ns_per_pixel"]))
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    doc = json.load(open(sys.argv[1]))
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.8))
    ax = axes[0]
    res_order = list(OrderedDict.fromkeys(r["resolution"] for r in doc["by_resolution"]))
    for m, pts in series(doc["by_resolution"], "resolution").items():
        ax.plot([res_order.index(x) for x, _ in pts], [y for _, y in pts], "-o", label=m)
    ax.set_xticks(range(len(res_order)))
    ax.set_xticklabels(res_order)
    ax.set_title("against resolution (flat = no per-launch overhead)")
    ax = axes[1]
    for m, pts in series(doc["by_map_size"], "map_size").items():
        ax.plot([x for x, _ in pts], [y for _, y in pts], "-o", label=m)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("height map side (texels)")
    ax.set_title("against height-map size")
    ax = axes[2]
    for m, pts in series(doc["by_steps"], "steps").items():
        ax.plot([x for x, _ in pts], [y for _, y in pts], "-o", label=m)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("steps (layers, linear steps, samples, sphere steps)")
    ax.set_title("against step count (linear = slope 1)")
    for a in axes[:3]:
        a.set_yscale("log")
        a.set_ylabel("kernel ns/pixel")
        a.grid(True, which="both", alpha=0.25)
        a.legend(fontsize=7)
    ax = axes[3]
    rows = doc["methods"]
    y = list(range(len(rows)))
    ax.barh([k - 0.2 for k in y], [100 * r["roofline_ratio"] for r in rows], height=0.4,
            color="tab:blue", label="line roof (independent fetches)")
    ax.barh([k + 0.2 for k in y], [100 * r.get("chain_roofline_ratio", 0) for r in rows],
            height=0.4, color="tab:orange", label="chain roof (dependent fetches)")
    ax.set_xlim(0, max(150, 10 + max(100 * r.get("chain_roofline_ratio", 0) for r in rows)))
    ax.legend(fontsize=7, loc="lower right")
    ax.set_yticks(y)
    ax.set_yticklabels(["%s (%.1f fetches)" % (r["method"], r["fetches_per_pixel"]) for r in rows],
                       fontsize=8)
    ax.invert_yaxis()
    ax.axvline(70, color="black", linestyle="--", linewidth=1)
    ax.set_xlabel("% of roof (pass-through + fetches x ns/fetch)")
    ax.set_title("defaults against the device's roofline")
    fig.suptitle("%s, %s" % (doc["device"], doc["driver"]), fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2] + "/bench-growth.png", dpi=95)
    print("wrote %s/bench-growth.png" % sys.argv[2])


if __name__ == "__main__":
    main()
