#!/usr/bin/python3
"""Accuracy against cost charts from `offsetmap sweep` (sweep.json).

    /usr/bin/python3 tools/bench/plot_sweep.py sweep.json OUT_DIR

Writes OUT_DIR/pareto-ns.png (mean uv error against kernel ns/pixel) and OUT_DIR/pareto-fetches.png
(against height fetches/pixel): log axes, one colour per method, each method's settings joined in
order of cost, the Pareto front (no other point is both cheaper and more accurate) drawn and its
members named; OUT_DIR/pareto-by-map.png, the ns/pixel chart per height map; and
OUT_DIR/pareto-cheap.png, the cheap end (at most 8 fetches): p95 uv error against fetches, with half
of parallax-iterative's p95 (interpolated between its settings) drawn as the line to beat. Every
point is the mean over the sweep's height maps and view sets (p95: the mean of each case's p95).
`exact` (zero error) sits on the error floor.
A material frame (`sweep --materials`, map "materials": every method for all materials at once, and
the table's own methods as "per-material", drawn as a star) has its own panel in pareto-by-map.png
and stays out of the means.
Needs Debian's python3-matplotlib.
"""
import json
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ERROR_FLOOR = 1e-4  # texels: zero error is drawn here on the log axis
FETCH_FLOOR = 0.5   # fetches/pixel: zero fetches is drawn here


def aggregate(records, key_filter=None):
    points = OrderedDict()
    for r in records:
        if key_filter and not key_filter(r):
            continue
        key = (r["method"], r["setting"])
        points.setdefault(key, []).append(r)
    out = []
    for (method, setting), rs in points.items():
        mean = lambda f: sum(x[f] for x in rs) / len(rs)
        out.append({"method": method, "setting": setting, "error": mean("uv_mean"),
                    "ns": mean("ns_per_pixel"), "fetches": mean("fetches_mean"),
                    "psnr": mean("psnr_db"), "p95": mean("uv_p95")})
    return out


CHEAP_FETCHES = 8.0
BASELINE = "parallax-iterative"


def interpolate(curve, x):
    """Piecewise linear through sorted (x, y) points, flat beyond the ends."""
    if x <= curve[0][0]:
        return curve[0][1]
    for (x0, y0), (x1, y1) in zip(curve, curve[1:]):
        if x <= x1:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return curve[-1][1]


def draw_cheap(points, where, path):
    """p95 against fetches at the cheap end; returns the best point at 2-4 fetches against half of
    the baseline's p95 at its fetches (None without a baseline)."""
    cheap = [p for p in points if 0 < p["fetches"] <= CHEAP_FETCHES]
    base = sorted((p["fetches"], p["p95"]) for p in cheap if p["method"] == BASELINE)
    fig, ax = plt.subplots(figsize=(10, 6.5))
    colours = plt.get_cmap("tab10")
    for i, m in enumerate(OrderedDict.fromkeys(p["method"] for p in points)):
        ps = sorted((p for p in cheap if p["method"] == m), key=lambda p: p["fetches"])
        if not ps:
            continue
        ax.plot([p["fetches"] for p in ps], [max(p["p95"], ERROR_FLOOR) for p in ps], "-o",
                color=colours(i % 10), label=m, markersize=4, linewidth=1)
    best = None
    if len(base) >= 2:
        xs = [base[0][0] + (CHEAP_FETCHES - base[0][0]) * k / 100 for k in range(101)]
        ax.plot(xs, [0.5 * interpolate(base, x) for x in xs], ":", color="black",
                label="half of %s's p95" % BASELINE)
        for p in cheap:
            if 2.0 <= p["fetches"] <= 4.0 and p["method"] != BASELINE:
                ratio = p["p95"] / interpolate(base, p["fetches"])
                if best is None or ratio < best[1]:
                    best = (p, ratio)
        if best:
            p, ratio = best
            # Beside its own point, ringed, so that no neighbour reads as the one meant.
            ax.plot([p["fetches"]], [max(p["p95"], ERROR_FLOOR)], "o", markersize=11,
                    markerfacecolor="none", markeredgecolor="black")
            ax.annotate("%s\n%.2f x %s's p95 at %.2f fetches" % (label(p), ratio, BASELINE,
                                                                   p["fetches"]),
                        (p["fetches"], max(p["p95"], ERROR_FLOOR)), fontsize=8, xytext=(10, -4),
                        textcoords="offset points", va="top",
                        bbox={"boxstyle": "round", "fc": "white", "ec": "0.6", "alpha": 0.85})
    ax.set_yscale("log")
    ax.set_xlabel("height fetches per pixel")
    ax.set_ylabel("p95 uv error against exact (texels; mean over cases)")
    ax.set_title("The cheap end: " + where, fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return best


def pareto(points, cost):
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (p[cost], p["error"])):
        if p["error"] < best:
            front.append(p)
            best = p["error"]
    return front


def label(p):
    return p["method"] if p["setting"] == "defaults" else p["method"] + " " + p["setting"]


def draw(ax, points, cost, floor, title, annotate=True):
    methods = list(OrderedDict.fromkeys(p["method"] for p in points))
    colours = plt.get_cmap("tab10")
    for i, m in enumerate(methods):
        # A method's settings joined in order of cost: its grid may hold more than one rule.
        ps = sorted((p for p in points if p["method"] == m), key=lambda p: p[cost])
        xs = [max(p[cost], floor) for p in ps]
        ys = [max(p["error"], ERROR_FLOOR) for p in ps]
        if m == "per-material":
            ax.plot(xs, ys, "*", color="red", label=m, markersize=14)
            continue
        ax.plot(xs, ys, "-o", color=colours(i % 10), label=m, markersize=4, linewidth=1)
    front = pareto(points, cost)
    ax.step([max(p[cost], floor) for p in front], [max(p["error"], ERROR_FLOOR) for p in front],
            where="post", color="black", linestyle="--", linewidth=1, label="Pareto front")
    if annotate:
        for p in front:
            ax.annotate(label(p), (max(p[cost], floor), max(p["error"], ERROR_FLOOR)), fontsize=7,
                        xytext=(4, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylabel("mean uv error against exact (texels)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.25)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        doc = json.load(f)
    records, out = doc["records"], sys.argv[2]
    points = aggregate(records, lambda r: r["map"] != "materials")
    maps = sorted(set(r["map"] for r in records if r["map"] != "materials"))
    views = sorted(set(r["views"] for r in records if r["map"] != "materials"))
    where = "%d height maps x %d view sets (%s)\n%s" % (len(maps), len(views), ", ".join(views),
                                                        doc.get("device", ""))
    for cost, floor, xlabel, name in (
            ("ns", 0, "kernel time per pixel (ns, median of runs)", "pareto-ns.png"),
            ("fetches", FETCH_FLOOR, "height fetches per pixel (0 drawn at 0.5)", "pareto-fetches.png")):
        fig, ax = plt.subplots(figsize=(10, 7))
        draw(ax, points, cost, floor, "Accuracy against cost: " + where)
        ax.set_xlabel(xlabel)
        ax.legend(fontsize=8, loc="lower left")
        fig.tight_layout()
        fig.savefig(out + "/" + name, dpi=110)
        plt.close(fig)
    best = draw_cheap(points, where, out + "/pareto-cheap.png")
    if best:
        print("cheap end: %s, p95 %.3g texels at %.2f fetches: %.2f x %s's there" % (
            label(best[0]), best[0]["p95"], best[0]["fetches"], best[1], BASELINE))
    if any(r["map"] == "materials" for r in records):
        maps.append("materials")
    cols = min(4, len(maps))
    rows = (len(maps) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.6 * rows), squeeze=False)
    for ax, m in zip(axes.flat, maps):
        title = m if m != "materials" else "material frame (pooled; star: per-material)"
        draw(ax, aggregate(records, lambda r: r["map"] == m), "ns", 0, title, annotate=False)
        ax.set_xlabel("ns/pixel")
    for ax in list(axes.flat)[len(maps):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=6, loc="lower left")
    fig.tight_layout()
    fig.savefig(out + "/pareto-by-map.png", dpi=90)
    print("wrote %s/pareto-ns.png, pareto-fetches.png, pareto-by-map.png, pareto-cheap.png" % out)


if __name__ == "__main__":
    main()
