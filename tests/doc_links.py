#!/usr/bin/env python3
"""Every relative link and image in README.md and docs/*.md resolves: the file exists in the
repository and, with a #fragment into a Markdown page, the page has that heading (GitHub's
anchors: lower case, punctuation dropped, spaces to hyphens, -1, -2 ... for repeats). Links inside
code blocks and spans are not links; absolute URLs are not checked (CI has no network).
Standard library only."""
import functools
import os
import re
import sys

from readme_figures import ROOT, pages  # the same pages the figure check reads

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
FENCE = re.compile(r"^(```|~~~)")


def prose(text):
    """The page without fenced blocks, indented code blocks and code spans."""
    out, fenced = [], False
    for line in text.splitlines():
        if FENCE.match(line.strip()):
            fenced = not fenced
            continue
        if fenced or line.startswith("    ") and not line.lstrip().startswith(("-", "*", "|")):
            out.append("")
            continue
        out.append(re.sub(r"`[^`]*`", "", line))
    return out


@functools.lru_cache(maxsize=None)
def anchors(path):
    seen, found = {}, set()
    fenced = False
    for line in open(path, encoding="utf-8"):
        if FENCE.match(line.strip()):
            fenced = not fenced
        m = None if fenced else re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        slug = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        found.add(slug if n == 0 else f"{slug}-{n}")
    return found


def main():
    problems, checked = [], 0
    for page in pages():
        rel_page = os.path.relpath(page, ROOT)
        with open(page, encoding="utf-8") as f:
            lines = prose(f.read())
        for number, line in enumerate(lines, 1):
            for m in LINK.finditer(line):
                target = m.group(1)
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):
                    continue
                checked += 1
                path, _, fragment = target.partition("#")
                full = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
                where = f"{rel_page} line {number}: {target}"
                if not full.startswith(ROOT + os.sep) and full != ROOT:
                    problems.append(f"{where}: outside the repository")
                elif not os.path.exists(full):
                    problems.append(f"{where}: no such file")
                elif fragment and full.endswith(".md") and fragment not in anchors(full):
                    problems.append(f"{where}: no heading with that anchor")
    for p in problems:
        print("doc_links:", p)
    print(f"doc_links: {checked} links in {len(pages())} pages checked"
          + (f", {len(problems)} do not resolve" if problems else ", all resolve"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
