"""Plots the joint history written by `cargo run --example urdf_arm -- --csv FILE` into a PNG.

Usage: python scripts/plot_arm.py arm.csv docs/arm_joints.png

Needs only Pillow (it comes with rerun-sdk). Three stacked panels: shoulder and elbow angles
[rad] with their upper limits (dashed), wrist slide [mm] with its upper limit.
"""

import csv
import sys

from PIL import Image, ImageDraw

W, H, PAD_L, PAD_R, PAD_T, PANEL_H, GAP = 900, 620, 80, 20, 40, 160, 30
COLORS = [(200, 40, 40), (40, 90, 200), (30, 140, 60)]


def main():
    src, dst = sys.argv[1], sys.argv[2]
    rows = list(csv.DictReader(open(src)))
    t = [float(r["t"]) for r in rows]
    series = [
        ("shoulder [rad]", [float(r["shoulder"]) for r in rows], 0.6),
        ("elbow [rad]", [float(r["elbow"]) for r in rows], 0.8),
        ("wrist [mm]", [1e3 * float(r["wrist"]) for r in rows], 50.0),
    ]
    img = Image.new("RGB", (W, H), "white")
    d = ImageDraw.Draw(img)
    d.text((PAD_L, 10), "URDF arm (assets/urdf/arm.urdf) under gravity: KJOINT2 joints, friction and stops", fill="black")
    t0, t1 = t[0], t[-1]
    for k, (name, ys, limit) in enumerate(series):
        top = PAD_T + k * (PANEL_H + GAP)
        lo, hi = min(min(ys), limit, 0.0), max(max(ys), limit)
        span = (hi - lo) or 1.0
        lo, hi = lo - 0.08 * span, hi + 0.08 * span
        x = lambda tt: PAD_L + (tt - t0) / (t1 - t0) * (W - PAD_L - PAD_R)
        y = lambda v: top + PANEL_H - (v - lo) / (hi - lo) * PANEL_H
        d.rectangle([PAD_L, top, W - PAD_R, top + PANEL_H], outline=(120, 120, 120))
        for v in (lo + (hi - lo) * f for f in (0.0, 0.5, 1.0)):
            d.text((5, y(v) - 6), f"{v:8.3f}", fill=(80, 80, 80))
        # limit (dashed)
        xs = PAD_L
        while xs < W - PAD_R:
            d.line([xs, y(limit), min(xs + 8, W - PAD_R), y(limit)], fill=(150, 150, 150))
            xs += 14
        pts = [(x(a), y(b)) for a, b in zip(t, ys)]
        d.line(pts, fill=COLORS[k], width=2)
        d.text((W - PAD_R - 330, top + PANEL_H - 20), f"{name}   (dashed: URDF upper limit {limit:g})", fill=COLORS[k])
    bottom = PAD_T + 3 * (PANEL_H + GAP) - GAP
    for f in range(0, 5):
        tt = t0 + (t1 - t0) * f / 4
        d.text((PAD_L + (tt - t0) / (t1 - t0) * (W - PAD_L - PAD_R) - 10, bottom + 5), f"{tt:.1f} s", fill="black")
    img.save(dst)
    print(f"wrote {dst}")


if __name__ == "__main__":
    main()
