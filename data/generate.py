#!/usr/bin/python3
"""Writes the small height maps used by the demo, tests and benchmarks (16-bit PNG, H in [0,1],
white = high, tiling seamlessly). Deterministic: the same files on every run.

    /usr/bin/python3 data/generate.py [output folder, default: this script's folder]

Needs Debian's python3-numpy and python3-openimageio.
  rocks.png   256x256  rounded bricks with mortar grooves and fine grain (the demo's default)
  bumps.png   256x256  smooth sum of tiling sines (gentle slopes)
  noise.png   128x128  high-frequency value noise
"""
import os
import sys

import numpy as np
import OpenImageIO as oiio


def save(path, h):
    h = np.clip(h, 0.0, 1.0)
    spec = oiio.ImageSpec(h.shape[1], h.shape[0], 1, "uint16")
    out = oiio.ImageOutput.create(path)
    out.open(path, spec)
    # OIIO 2.4's Python write_image mis-writes a 2-D array: pass (h, w, 1).
    out.write_image(np.round(h * 65535).astype(np.uint16).reshape(h.shape[0], h.shape[1], 1))
    out.close()


def grid(n):
    c = (np.arange(n) + 0.5) / n
    return np.meshgrid(c, c)  # u along columns, v along rows


def bumps(n=256):
    u, v = grid(n)
    h = 0.5 + 0.25 * np.sin(2 * np.pi * 2 * u) * np.cos(2 * np.pi * 3 * v) \
        + 0.15 * np.sin(2 * np.pi * (u + 2 * v)) + 0.1 * np.cos(2 * np.pi * 4 * u)
    return (h - h.min()) / (h.max() - h.min())


def value_noise(n, cells, rng):
    """Tiling bicubic-smoothed value noise with `cells` lattice cells per side."""
    lattice = rng.random((cells, cells))
    u, v = grid(n)
    x, y = u * cells, v * cells
    i, j = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - i, y - j
    sx, sy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
    l = lambda a, b: lattice[b % cells, a % cells]
    top = l(i, j) * (1 - sx) + l(i + 1, j) * sx
    bot = l(i, j + 1) * (1 - sx) + l(i + 1, j + 1) * sx
    return top * (1 - sy) + bot * sy


def noise(n=128):
    rng = np.random.default_rng(7)
    h = 0.6 * value_noise(n, 32, rng) + 0.4 * value_noise(n, 64, rng)
    return (h - h.min()) / (h.max() - h.min())


def rocks(n=256):
    """4 x 8 running-bond bricks: rounded tops, steep sides, deep mortar, a little grain."""
    u, v = grid(n)
    rows, cols = 8, 4
    y = v * rows
    row = np.floor(y).astype(int)
    x = u * cols + 0.5 * (row % 2)
    fx, fy = x - np.floor(x), y - row
    # Distance to the brick's edge in brick-height units (bricks are twice as wide as tall).
    edge = np.minimum(np.minimum(fx, 1 - fx) * (rows / cols), np.minimum(fy, 1 - fy))
    mortar = 0.06
    body = np.clip((edge - mortar) / 0.12, 0.0, 1.0)
    body = np.sin(0.5 * np.pi * body) ** 0.7
    rng = np.random.default_rng(3)
    brick_id = (row * 131 + np.floor(x).astype(int) * 17) % 97
    tilt = 0.08 * np.sin(brick_id * 1.7) * (fx - 0.5)
    grain = 0.06 * value_noise(n, 64, rng)
    h = 0.12 + 0.78 * body + body * (tilt + grain)
    return np.clip(h, 0.0, 1.0)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    for name, fn in (("rocks", rocks), ("bumps", bumps), ("noise", noise)):
        save(os.path.join(out, name + ".png"), fn())
        print("wrote", os.path.join(out, name + ".png"))
