#!/usr/bin/python3
"""Draws one rendered stereo pair with the ground-truth visible lines overlaid (docs/rendering.md).

    /usr/bin/python3 scripts/plot_render_pair.py DIR OUT.png [--frame K]

DIR is the output of `simulate CONFIG --out DIR --images`: the images are read from
DIR/mav0/cam0|cam1 (data.csv, data/*.png), or in KITTI's layout from DIR/image_0|image_1, the
ground truth from DIR/seq.json (the noise-free visible segments when the config's
noise.endpoint_px is 0). Wide images (KITTI's) are drawn one above the other. Writes OUT.png
atomically. The README's pictures:

    echo '{"scene": {"type": "room"}, "frames": 2, "noise": {"endpoint_px": 0}}' > /tmp/room.json
    build/bin/simulate /tmp/room.json --out /tmp/room --images
    /usr/bin/python3 scripts/plot_render_pair.py /tmp/room results/render/room_stereo_pair.png
    build/bin/simulate street --out /tmp/street --images
    /usr/bin/python3 scripts/plot_render_pair.py /tmp/street results/render/street_stereo_pair.png --frame 50

Needs matplotlib (Debian: python3-matplotlib).
"""

import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def image_path(directory, camera, frame):
    kitti = os.path.join(directory, "image_0" if camera == "cam0" else "image_1")
    if os.path.isdir(kitti):
        return os.path.join(kitti, "%06d.png" % frame)
    with open(os.path.join(directory, "mav0", camera, "data.csv")) as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    return os.path.join(directory, "mav0", camera, "data", rows[frame][1].strip())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir")
    parser.add_argument("out")
    parser.add_argument("--frame", type=int, default=0)
    args = parser.parse_args()
    with open(os.path.join(args.dir, "seq.json")) as f:
        frame = json.load(f)["frames"][args.frame]
    wide = mpimg.imread(image_path(args.dir, "cam0", args.frame)).shape[1] > 2.5 * \
        mpimg.imread(image_path(args.dir, "cam0", args.frame)).shape[0]
    fig, axes = plt.subplots(2, 1, figsize=(12.8, 8.2), dpi=85) if wide else plt.subplots(1, 2, figsize=(12.8, 5.0), dpi=85)
    for ax, camera, side in zip(axes, ("cam0", "cam1"), ("left", "right")):
        image = mpimg.imread(image_path(args.dir, camera, args.frame))
        ax.imshow(image, cmap="gray", vmin=0.0, vmax=1.0, interpolation="nearest")
        # Pixel centres at integers (docs/conventions.md), as imshow draws them.
        for _, u1, v1, u2, v2 in frame[side]:
            ax.plot([u1, u2], [v1, v2], color="#ff3b1f", linewidth=0.9, alpha=0.85)
        ax.set_xlim(-0.5, image.shape[1] - 0.5)
        ax.set_ylim(image.shape[0] - 0.5, -0.5)
        ax.set_title(f"{side} camera, frame {args.frame}: {len(frame[side])} visible ground-truth lines", fontsize=10)
        ax.axis("off")
    fig.tight_layout()
    temporary = args.out + ".tmp.png"
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    fig.savefig(temporary)
    os.replace(temporary, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
