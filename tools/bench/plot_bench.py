#!/usr/bin/python3
"""Cost-growth charts from `offsetmap_bench` (bench.json).

    /usr/bin/python3 tools/bench/plot_bench.py bench.json OUT_DIR

Writes OUT_DIR/bench-growth.png: kernel ns/pixel against resolution (should be flat), against
height-map size (cache effects) and against step count (should be linear), plus the methods at
their defaults as a share of the device's fetch roofline; and, when the bench ran the GLSL peer,
OUT_DIR/bench-glsl-peer.png: each method's kernel against the same method in a fragment shader,
ns/pixel side by side with the kernel's speed-up written on each pair; for `--groups`,
plot_groups.py's chart. Needs Debian's python3-matplotlib.
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
    peer = doc.get("glsl_peer", {})
    if "groups" in doc:  # offsetmap_bench --groups
        from plot_groups import plot_groups
        plot_groups(doc, sys.argv[2])
        return
    if "by_resolution" not in doc:  # offsetmap_bench --glsl-peer: that chart alone
        if peer.get("rows"):
            plot_peer(peer, doc, sys.argv[2])
        return
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
    if peer.get("rows"):
        plot_peer(peer, doc, sys.argv[2])


def plot_peer(peer, doc, out_dir):
    rows = peer["rows"]
    fig, ax = plt.subplots(figsize=(8, 4.2))
    x = list(range(len(rows)))
    ax.bar([k - 0.2 for k in x], [r["kernel_ns_per_pixel"] for r in rows], width=0.4,
           color="tab:blue", label="offset kernel (%s)" % doc["device"].split("/")[0].strip())
    ax.bar([k + 0.2 for k in x], [r["glsl_ns_per_pixel"] for r in rows], width=0.4,
           color="tab:gray", label="GLSL full-screen pass (%s)" % peer["gl_renderer"])
    for k, r in enumerate(rows):
        top = max(r["kernel_ns_per_pixel"], r["glsl_ns_per_pixel"])
        ax.text(k, top * 1.03, "%.2fx" % r["kernel_speedup"], ha="center", fontsize=8)
    ax.set_xticks(x)
    ax.set_xticklabels(["%s\n%s" % (r["method"], r["scene"]) for r in rows], fontsize=8)
    ax.set_ylabel("ns/pixel (wall clock, timed in turns)")
    ax.set_ylim(0, 1.12 * max(max(r["kernel_ns_per_pixel"], r["glsl_ns_per_pixel"]) for r in rows))
    ax.set_title("kernels against the fragment-shader peer, %s: same steps and parameters"
                 % peer["resolution"], fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(True, axis="y", alpha=0.25)
    fig.tight_layout()
    fig.savefig(out_dir + "/bench-glsl-peer.png", dpi=95)
    print("wrote %s/bench-glsl-peer.png" % out_dir)


if __name__ == "__main__":
    main()
