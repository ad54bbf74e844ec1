#!/usr/bin/python3
"""Crops the same rectangle out of several PNGs and sets them side by side, each with a caption.

    /usr/bin/python3 docs/crop_figure.py OUT.png X0 Y0 X1 Y1 SCALE IMAGE CAPTION [IMAGE CAPTION ...]

Used by docs/regenerate.sh for the pages' close-ups. Needs Debian's python3-pil.
"""
import sys

from PIL import Image, ImageDraw, ImageFont


def main():
    if len(sys.argv) < 9 or (len(sys.argv) - 7) % 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    box = tuple(int(v) for v in sys.argv[2:6])
    scale = float(sys.argv[6])
    pairs = list(zip(sys.argv[7::2], sys.argv[8::2]))
    w, h = int((box[2] - box[0]) * scale), int((box[3] - box[1]) * scale)
    font = ImageFont.truetype("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", 13)
    band = 22
    sheet = Image.new("RGB", (len(pairs) * (w + 6) - 6, h + band), (24, 24, 28))
    draw = ImageDraw.Draw(sheet)
    for k, (path, caption) in enumerate(pairs):
        tile = Image.open(path).convert("RGB").crop(box).resize((w, h), Image.NEAREST)
        sheet.paste(tile, (k * (w + 6), band))
        draw.text((k * (w + 6) + 4, 3), caption, fill=(235, 235, 235), font=font)
    sheet.save(out)
    print("wrote " + out)


if __name__ == "__main__":
    main()
