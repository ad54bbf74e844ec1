#!/usr/bin/env python3
"""The pages' numbers against the files that measured them, so no figure goes stale silently.

    readme_figures.py [--figures DIR] [--write] [PAGE...]

PAGE: README.md and every docs/*.md by default. Two kinds of places in a page:
  - a number followed by a marker <!--f:SOURCE SELECTOR[ *K][ bound]--> (invisible when
    rendered): the number must be the source's value (times K) written to the precision shown,
    or, with `bound`, at least that value (for figures set by float rounding, which differ
    between CPUs: the README states a bound, "below 2e-4");
  - a generated table between <!--table:NAME--> and <!--/table-->: it must be what the
    generator below writes from the data.
SOURCE is `test` (figures the test suite records, support.hpp record_figure, in --figures DIR:
fresh from this build; +-1 in the last digit shown is allowed, for float differences between
CPUs) or a file under docs/data (measured by docs/regenerate.sh): `demo`, `bench`, `bench1`
(JSON: a path such as methods[method=pom].ns_per_pixel), `sweep`, `temporal`,
`failure-rocks-clamp` ... (CSV: `[agg:]column|key=value|key<=value...`, agg mean (default), min,
max, over the matching rows). --write rewrites every marked number and table from the data
(for docs/regenerate.sh runs); without it, a mismatch is listed and the exit status is 1.
Standard library only.
"""
import argparse
import csv
import glob
import json
import math
import os
import re
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
DATA = os.path.join(ROOT, "docs", "data")

MARK = re.compile(r"<!--f:(\S+) (.*?)(?: \*(\S+))?( bound)?-->")
NUMBER = re.compile(r"(\d[\d,]*(?:\.\d+)?(?:e[-+]?\d+)?)(\s*%?)$")
TABLE = re.compile(r"<!--table:(\S+)-->\n(.*?)<!--/table-->", re.S)


class Sources:
    def __init__(self, figures_dir):
        self.figures_dir = figures_dir
        self.cache = {}

    def test(self):
        if "test" not in self.cache:
            merged = {}
            for path in sorted(glob.glob(os.path.join(self.figures_dir or "", "*.json"))):
                with open(path) as f:
                    merged.update(json.load(f))
            self.cache["test"] = merged
        return self.cache["test"]

    def data(self, name):
        if name not in self.cache:
            for ext in (".json", ".csv"):
                path = os.path.join(DATA, ("demo-summary" if name == "demo" else
                                           "bench-run1" if name == "bench1" else name) + ext)
                if os.path.exists(path):
                    with open(path, newline="") as f:
                        self.cache[name] = json.load(f) if ext == ".json" else list(csv.DictReader(f))
                    break
            else:
                raise KeyError(f"no data file for '{name}' in docs/data")
        return self.cache[name]

    def value(self, source, selector):
        if source == "test":
            figs = self.test()
            if selector not in figs:
                raise KeyError(f"the tests recorded no figure '{selector}'")
            return figs[selector]
        data = self.data(source)
        return json_path(data, selector) if isinstance(data, dict) else csv_select(data, selector)


def json_path(data, path):
    node = data
    for part in re.findall(r"[^.\[\]]+|\[[^\]]*\]", path):
        if part.startswith("["):
            inner = part[1:-1]
            if inner.isdigit():
                node = node[int(inner)]
                continue
            conds = [c.split("=", 1) for c in inner.split(",")]
            hits = [x for x in node if all(str(x.get(k)) == v for k, v in conds)]
            if len(hits) != 1:
                raise KeyError(f"{path}: [{inner}] matches {len(hits)} entries")
            node = hits[0]
        else:
            if part not in node:
                raise KeyError(f"{path}: no '{part}'")
            node = node[part]
    return float(node)


OPS = {"<=": lambda a, b: a <= b, ">=": lambda a, b: a >= b, "<": lambda a, b: a < b,
       ">": lambda a, b: a > b}


def csv_select(rows, selector):
    parts = selector.split("|")
    agg, _, column = parts[0].rpartition(":")
    sel = rows
    for cond in parts[1:]:
        m = re.match(r"([A-Za-z_]+)(<=|>=|<|>|=)(.*)$", cond)
        if not m:
            raise KeyError(f"bad condition '{cond}'")
        key, op, val = m.groups()
        if op == "=":
            sel = [r for r in sel if r[key] == val]
        else:
            sel = [r for r in sel if OPS[op](float(r[key]), float(val))]
    if not sel:
        raise KeyError(f"'{selector}' matches no row")
    vals = [float(r[column]) for r in sel]
    return {"": sum(vals) / len(vals), "mean": sum(vals) / len(vals), "max": max(vals),
            "min": min(vals)}[agg]


def shown_like(written, value):
    """value written with the precision (decimals, or significant digits in e-notation) of
    `written`."""
    w = written.replace(",", "")
    if "e" in w:
        mant = w.split("e")[0]
        digits = len(mant.split(".")[1]) if "." in mant else 0
        text = f"{value:.{digits}e}"
        m, e = text.split("e")
        return f"{m}e{int(e)}"
    decimals = len(w.split(".")[1]) if "." in w else 0
    text = f"{value:.{decimals}f}"
    if "," in written:
        ip, _, fp = text.partition(".")
        text = f"{int(ip):,}" + (("." + fp) if fp else "")
    return text


def last_digit(written):
    w = written.replace(",", "")
    if "e" in w:
        mant, e = w.split("e")
        d = len(mant.split(".")[1]) if "." in mant else 0
        return 10.0 ** (int(e) - d)
    return 10.0 ** -(len(w.split(".")[1]) if "." in w else 0)


# Generated tables.
def table_demo(src):
    d = src.data("demo")
    rows = ["| method | mean uv error (texels) | p95 | > 1 texel | fetches/pixel | ns/pixel | "
            "precomputed |", "|---|---|---|---|---|---|---|"]
    for m in d["methods"]:
        pre = ""
        if m["precomputed_bytes"]:
            ms = m["precompute_ms"]
            pre = (f"{m['precomputed_bytes'] / 1048576:.1f} MB, "
                   + (f"{ms:.0f} ms" if ms >= 1 else "< 1 ms"))
        rows.append(f"| {m['method']} | {sig(m['mean_err_texels'])} | {sig(m['p95_err_texels'])} "
                    f"| {percent(m['wrong_surface_share'])} | {sig(m['fetches_per_pixel'])} | "
                    f"{sig(m['ns_per_pixel'])} | {pre} |")
    return "\n".join(rows) + "\n"


def table_throughput(src):
    b, b1 = src.data("bench"), src.data("bench1")
    first = {m["method"]: m for m in b1["methods"]}
    rows = ["| method | ns/pixel | Mpix/s | fetches/pixel | % of line roof (run 1 / 2) | "
            "% of chain roof (run 1 / 2) | lanes busy | × threaded C++ loop |",
            "|---|---|---|---|---|---|---|---|"]
    for m in b["methods"]:
        name = m["method"]
        r1 = first.get(name, m)
        if m["fetches_per_pixel"] > 0:
            line = f"{100 * r1['roofline_ratio']:.0f} / {100 * m['roofline_ratio']:.0f} %"
            chain = (f"{100 * r1['chain_roofline_ratio']:.0f} / "
                     f"{100 * m['chain_roofline_ratio']:.0f} %")
        else:
            line = (f"{100 * b1['none_vs_memcpy']['none_vs_memcpy']:.0f} / "
                    f"{100 * b['none_vs_memcpy']['none_vs_memcpy']:.0f} % of host memcpy")
            chain = "—"
        busy = f"{100 * m['lanes_busy']:.0f} %" if m["fetches_per_pixel"] > 1.5 else "—"
        peer = f"{m['kernel_vs_loop']:.1f}" if "kernel_vs_loop" in m else "—"
        rows.append(f"| {name} | {sig(m['ns_per_pixel'])} | {m['mpix_per_s']:.0f} | "
                    f"{sig(m['fetches_per_pixel'])} | {line} | {chain} | {busy} | {peer} |")
    return "\n".join(rows) + "\n"


def table_temporal(src):
    rows = src.data("temporal")
    methods = []
    for r in rows:
        if r["method"] not in methods and r["method"] != "exact":
            methods.append(r["method"])
    head = "| " + " | ".join(methods) + " |"
    rule = "|" + "---|" * len(methods)
    cells = []
    for m in methods:
        sel = [r for r in rows if r["method"] == m]
        mean = sum(float(r["mean"]) for r in sel) / len(sel)
        pop = sum(float(r["pop_share"]) for r in sel) / len(sel)
        cells.append(f"{mean:.2f} ({100 * pop:.1f} %)")
    return "\n".join([head, rule, "| " + " | ".join(cells) + " |"]) + "\n"


def table_grazing(src):
    rows = ["| policy | parallax ≤ 5° | parallax 10–25° | pom ≤ 5° | pom 10–25° | pom ≥ 35° | "
            "exact 10–25° |", "|---|---|---|---|---|---|---|"]
    bands = [("parallax", "|elevation_deg<=5"), ("parallax", "|elevation_deg>=10|elevation_deg<=25"),
             ("pom", "|elevation_deg<=5"), ("pom", "|elevation_deg>=10|elevation_deg<=25"),
             ("pom", "|elevation_deg>=35"), ("exact", "|elevation_deg>=10|elevation_deg<=25")]
    for policy, label in (("clamp", "clamp"), ("limit", "limit"), ("cap", "cap (32 texels)")):
        data = src.data(f"failure-rocks-{policy}")
        vals = [csv_select(data, f"uv_mean|method={m}{cond}") for m, cond in bands]
        rows.append(f"| {label} | " + " | ".join(sig(v) for v in vals) + " |")
    return "\n".join(rows) + "\n"


def table_ci(src):
    """CI's step table (.ci/run's last lines, docs/data/ci-steps.csv): wall time and share."""
    steps = src.data("ci-steps")
    total = sum(int(r["seconds"]) for r in steps if r["beside"] != "yes")
    rows = ["| step | tier | wall (m:ss) | share of CI |", "|---|---|---|---|"]
    for r in steps:
        s = int(r["seconds"])
        share = "beside" if r["beside"] == "yes" else f"{100 * s / total:.0f} %"
        rows.append(f"| {r['step']} | {r['tier']} | {s // 60}:{s % 60:02d} | {share} |")
    rows.append(f"| **total** | | **{total // 60}:{total % 60:02d}** | |")
    return "\n".join(rows) + "\n"


TABLES = {"demo": table_demo, "throughput": table_throughput, "temporal": table_temporal,
          "grazing": table_grazing, "ci": table_ci}


def sig(x):
    """Two or three significant digits, as the README's tables write them."""
    if x == 0 or abs(x - round(x)) < 1e-9 and abs(x) < 1e6:
        return f"{x:.0f}"
    a = abs(x)
    if a >= 100:
        return f"{x:.0f}"
    if a >= 10:
        return f"{x:.1f}"
    if a >= 1:
        return f"{x:.2f}"
    if a >= 0.1:
        return f"{x:.2f}"
    if a >= 0.01:
        return f"{x:.3f}"
    if a >= 1e-4:
        return f"{x:.2g}"
    m, e = f"{x:.1e}".split("e")
    return f"{m}e{int(e)}"


def percent(share):
    return "0 %" if share == 0 else f"{100 * share:.1f} %"


def pages():
    """README.md and every page under docs/: the figure check and doc_links.py read them all."""
    docs = os.path.join(ROOT, "docs")
    return [os.path.join(ROOT, "README.md")] + sorted(
        os.path.join(docs, f) for f in os.listdir(docs) if f.endswith(".md"))


def check_page(path, src, write, problems):
    """Checks (or, with write, rewrites) one page; returns its marked figures and tables."""
    name = os.path.relpath(path, ROOT)
    with open(path) as f:
        text = f.read()

    out, pos, checked = [], 0, 0
    for m in MARK.finditer(text):
        source, selector, scale, bound = m.group(1), m.group(2), m.group(3), m.group(4)
        before = text[pos:m.start()]
        num = NUMBER.search(before)
        where = f"{name} line {text.count(chr(10), 0, m.start()) + 1}"
        if not num:
            problems.append(f"{where}: no number before the marker {m.group(0)}")
            out.append(before + m.group(0))
            pos = m.end()
            continue
        written = num.group(1)
        try:
            value = src.value(source, selector) * (float(scale) if scale else 1.0)
        except (KeyError, ValueError, TypeError) as e:
            problems.append(f"{where}: {source} {selector}: {e}")
            out.append(before + m.group(0))
            pos = m.end()
            continue
        shown = shown_like(written, value)
        if bound:
            ok = value <= float(written.replace(",", ""))
            if not ok:  # the smallest bound at the precision shown that holds
                step = last_digit(written)
                shown = shown_like(written, math.ceil(value / step) * step)
        else:
            ok = shown.replace(",", "") == written.replace(",", "")
            if not ok and source == "test":
                ok = abs(float(written.replace(",", "")) - value) <= 1.0001 * last_digit(written)
        if not ok and not write:
            problems.append(f"{where}: written {written}, {source} {selector} gives {shown} ({value:.6g})"
                            + (" (the written number is a bound)" if bound else ""))
        checked += 1
        rewrite = write and not (bound and ok)
        new_before = before[:num.start(1)] + (shown if rewrite else written) + before[num.end(1):]
        out.append(new_before + m.group(0))
        pos = m.end()
    out.append(text[pos:])
    text2 = "".join(out)

    def replace_table(m):
        table, body = m.group(1), m.group(2)
        if table not in TABLES:
            problems.append(f"{name}: unknown generated table '{table}'")
            return m.group(0)
        try:
            want = TABLES[table](src)
        except (KeyError, ValueError) as e:
            problems.append(f"{name}: table {table}: {e}")
            return m.group(0)
        if want != body and not write:
            problems.append(f"{name}: table {table} differs from its data:\n{want}")
        return f"<!--table:{table}-->\n{want if write else body}<!--/table-->"

    text2 = TABLE.sub(replace_table, text2)
    tables = len(TABLE.findall(text))
    if write and text2 != text:
        with open(path, "w") as f:
            f.write(text2)
    return checked, tables


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--figures", help="the test suite's figures folder (build/<preset>/figures)")
    ap.add_argument("--write", action="store_true", help="rewrite the pages from the data")
    ap.add_argument("pages", nargs="*", help="the pages (default: README.md and docs/*.md)")
    args = ap.parse_args()
    src = Sources(args.figures)
    problems, checked, tables = [], 0, 0
    for path in args.pages or pages():
        c, t = check_page(path, src, args.write, problems)
        checked += c
        tables += t
    for p in problems:
        print("readme_figures:", p)
    print(f"readme_figures: {checked} marked figures and {tables} generated tables"
          + (" rewritten" if args.write else " checked") + (f", {len(problems)} problems" if problems else ""))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
