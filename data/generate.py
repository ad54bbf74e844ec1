#!/usr/bin/python3
"""Writes the small height maps used by the demo, tests and benchmarks (16-bit PNG, H in [0,1],
white = high, tiling seamlessly). Deterministic: the same files on every run.

    /usr/bin/python3 data/generate.py [output folder, default: this script's folder]

Needs Debian's python3-numpy and python3-openimageio.
  rocks.png   256x256  rounded bricks with mortar grooves and fine grain (brick-like cliffs; demo)
  bumps.png   256x256  smooth bumps: a sum of low-frequency tiling sines (gentle slopes)
  sines.png   256x256  a sine field: H = 1/2 + 1/2 sin(2 pi 4 u) sin(2 pi 4 v) (smooth, full range)
  noise.png   128x128  high-frequency value noise
  spikes.png  256x256  thin spikes (fur-like): 1-2 texel cones of random height on a low floor
  text.png    256x256  raised text ("OFFSET MAP"), bevelled by a small blur
  stairs.png  256x256  eight steps along u, each a cliff of 1/8
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


def sines(n=256):
    u, v = grid(n)
    return 0.5 + 0.5 * np.sin(2 * np.pi * 4 * u) * np.sin(2 * np.pi * 4 * v)


def spikes(n=256):
    rng = np.random.default_rng(11)
    h = np.full((n, n), 0.05)
    for _ in range(3000):
        ci, cj = rng.integers(0, n, 2)
        top = rng.uniform(0.5, 1.0)
        radius = rng.uniform(0.8, 2.0)  # texels
        for dj in range(-2, 3):
            for di in range(-2, 3):
                r = np.hypot(di, dj)
                if r <= radius:
                    j, i = (cj + dj) % n, (ci + di) % n
                    h[j, i] = max(h[j, i], top * (1 - r / (radius + 1)))
    return h


def text(n=256):
    buf = oiio.ImageBuf(oiio.ImageSpec(n, n, 1, "float"))
    oiio.ImageBufAlgo.render_text(buf, 16, 105, "OFFSET", 50, "DejaVuSans-Bold", (1.0,))
    oiio.ImageBufAlgo.render_text(buf, 42, 200, "MAP", 80, "DejaVuSans-Bold", (1.0,))
    mask = np.asarray(buf.get_pixels(oiio.FLOAT)).reshape(n, n)
    # A 5x5 box blur bevels the letters so the bilinear relief has slopes, not only walls.
    padded = np.pad(mask, 2, mode="wrap")
    soft = sum(padded[dj:dj + n, di:di + n] for dj in range(5) for di in range(5)) / 25.0
    return 0.15 + 0.75 * np.clip(soft * 1.4, 0.0, 1.0)


def stairs(n=256):
    u, _ = grid(n)
    return np.floor(u * 8) / 8 + 1.0 / 16


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    maps = (("rocks", rocks), ("bumps", bumps), ("sines", sines), ("noise", noise),
            ("spikes", spikes), ("text", text), ("stairs", stairs))
    for name, fn in maps:
        save(os.path.join(out, name + ".png"), fn())
        print("wrote", os.path.join(out, name + ".png"))
