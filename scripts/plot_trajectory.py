#!/usr/bin/python3
"""Draws camera trajectories (TUM or KITTI files) in plan and side views.

    scripts/plot_trajectory.py FILE [FILE ...] --out PLOT.png [--labels LABEL ...]
                               [--reference] [--format auto|tum|kitti] [--kitti-frame-period S]
                               [--errors METRICS.json] [--title TITLE]
    scripts/plot_trajectory.py --scene DIR [FILE ...] --out PLOT.png

Each FILE is a trajectory of world_from_cam poses (docs/formats.md), TUM (8 numbers a line) or
KITTI (12), told apart by the number of values on the first pose line unless --format says.
The views follow the camera axes of the first frame (docs/conventions.md: x right, y down,
z forward): plan view = x (right) against z (forward), side view = z against the height -y.
Each trajectory has its colour; its start is a dot and its end a cross of the same colour.

--reference   the first FILE is the ground truth: drawn black and dashed.
--errors      `evaluate`'s JSON with its per-frame curve (`evaluate --per-frame --json FILE`):
              adds the translation and rotation error against time below the views.
--scene DIR   a `simulate` output directory: draws its 3-D segments (DIR/scene.csv) in grey and
              its ground truth (DIR/gt.tum) as the reference, then any FILE given.

`evaluate --plot PLOT.png` runs this script with the aligned estimate and its errors.
scripts/plot_experiment.py uses its readers and views for the experiments' trajectory plots.
Needs matplotlib (Debian: python3-matplotlib, in /usr/bin/python3).
"""

import argparse
import csv
import json
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
except ImportError:
    sys.stderr.write(
        "plot_trajectory.py: error: matplotlib is not available for %s "
        "(Debian: apt-get install python3-matplotlib, then run with /usr/bin/python3)\n" % sys.executable
    )
    sys.exit(1)

COLORS = plt.rcParams["axes.prop_cycle"].by_key()["color"]
REFERENCE_STYLE = dict(color="black", linestyle="--", linewidth=1.2)
SEGMENT_STYLE = dict(color="0.55", linewidth=0.8)


class PlotError(Exception):
    """An input the script cannot use; the message names the file."""


def read_trajectory(path, fmt="auto", kitti_frame_period=0.1):
    """(times, positions) of a TUM or KITTI file; positions are (x, y, z) camera centres."""
    times, xyz = [], []
    try:
        with open(path) as f:
            for number, line in enumerate(f, 1):
                s = line.strip()
                if not s or s.startswith("#"):
                    continue
                try:
                    v = [float(t) for t in s.split()]
                except ValueError:
                    raise PlotError("%s:%d: not a list of numbers" % (path, number))
                if fmt == "auto":
                    fmt = {8: "tum", 12: "kitti"}.get(len(v))
                    if fmt is None:
                        raise PlotError("%s:%d: %d numbers: neither TUM (8) nor KITTI (12)" % (path, number, len(v)))
                if fmt == "tum" and len(v) == 8:
                    times.append(v[0])
                    xyz.append((v[1], v[2], v[3]))
                elif fmt == "kitti" and len(v) == 12:
                    times.append(len(times) * kitti_frame_period)
                    xyz.append((v[3], v[7], v[11]))
                else:
                    raise PlotError("%s:%d: expected %d numbers (%s), got %d"
                                    % (path, number, 8 if fmt == "tum" else 12, fmt.upper(), len(v)))
    except OSError as e:
        raise PlotError("%s: %s" % (path, e.strerror))
    if not xyz:
        raise PlotError("%s: no poses" % path)
    return times, xyz


def read_scene(path):
    """Segments ((x1, y1, z1), (x2, y2, z2)) of a simulate scene.csv."""
    segments = []
    try:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                segments.append(((float(row["x1"]), float(row["y1"]), float(row["z1"])),
                                 (float(row["x2"]), float(row["y2"]), float(row["z2"]))))
    except OSError as e:
        raise PlotError("%s: %s" % (path, e.strerror))
    except (KeyError, ValueError, TypeError):
        raise PlotError("%s: expected the columns id,x1,y1,z1,x2,y2,z2 of numbers" % path)
    return segments


def path_length(xyz):
    return sum(math.dist(xyz[k], xyz[k - 1]) for k in range(1, len(xyz)))


def distance_text(metres):
    """An error or a gap: mm below a metre, m above (a diverged run)."""
    return "%.3g mm" % (1000.0 * metres) if abs(metres) < 1.0 else "%.3g m" % metres


def length_text(metres):
    """A length with a precision that suits it: 0.698 m, 12.35 m, 1234 m."""
    return "%.3f m" % metres if metres < 10 else "%.2f m" % metres if metres < 100 else "%.0f m" % metres


def views(xyz):
    """((x, z), (z, height)) coordinate lists: the plan and the side view; height = -y."""
    return ([p[0] for p in xyz], [p[2] for p in xyz]), ([p[2] for p in xyz], [-p[1] for p in xyz])


def label_views(ax_plan, ax_side, suffix=""):
    ax_plan.set_title("Plan view" + suffix, fontsize=10)
    ax_side.set_title("Side view" + suffix, fontsize=10)
    ax_plan.set_xlabel("x, right (m)")
    ax_plan.set_ylabel("z, forward (m)")
    ax_side.set_xlabel("z, forward (m)")
    ax_side.set_ylabel("height, -y (m)")
    for ax in (ax_plan, ax_side):
        ax.grid(True, alpha=0.3)
        ax.set_aspect("equal", adjustable="datalim")


def draw_curve(ax_plan, ax_side, xyz, label, style):
    """One trajectory in both views, with its start (dot) and end (cross) in its colour."""
    for ax, (a, b) in zip((ax_plan, ax_side), views(xyz)):
        ax.plot(a, b, label=label, **style)
        ax.plot(a[0], b[0], "o", color=style["color"], markersize=6, zorder=5)
        ax.plot(a[-1], b[-1], "x", color=style["color"], markersize=9, markeredgewidth=2, zorder=5)


def draw_segments(ax_plan, ax_side, segments):
    # One collection per view: a street's 20 000 segments drawn one by one took half a minute.
    plan, side = [], []
    for p, q in segments:
        (pa, pb), (sa, sb) = views([p, q])
        plan.append(list(zip(pa, pb)))
        side.append(list(zip(sa, sb)))
    ax_plan.add_collection(LineCollection(plan, label="scene segments", **SEGMENT_STYLE))
    ax_side.add_collection(LineCollection(side, **SEGMENT_STYLE))
    for ax in (ax_plan, ax_side):
        ax.autoscale_view()


def marker_handles():
    """Legend entries explaining the start and end markers."""
    return ([plt.Line2D([], [], marker="o", color="0.3", linestyle=""),
             plt.Line2D([], [], marker="x", color="0.3", linestyle="", markeredgewidth=2, markersize=8)],
            ["start (dot, in the curve's colour)", "end (cross)"])


def read_errors(path):
    """evaluate's JSON: (per-frame curve, statistics of the translation and rotation errors)."""
    try:
        with open(path) as f:
            metrics = json.load(f)
    except OSError as e:
        raise PlotError("%s: %s" % (path, e.strerror))
    except ValueError as e:
        raise PlotError("%s: invalid JSON (%s)" % (path, e))
    curve = metrics.get("per_frame")
    if not curve or not all(k in curve for k in ("time_s", "trans_err_m", "rot_err_deg")):
        raise PlotError("%s: no per-frame curve (write it with evaluate --per-frame --json FILE)" % path)
    return curve, metrics.get("ate_trans_m"), metrics.get("ate_rot_deg")


def translation_unit(values):
    """mm for errors below a metre, m above: the numbers stay readable."""
    return (1000.0, "mm") if max(values, default=0.0) < 1.0 else (1.0, "m")


def draw_errors(ax_trans, ax_rot, curve, trans_stats, rot_stats, color):
    scale, unit = translation_unit(curve["trans_err_m"])
    ax_trans.plot(curve["time_s"], [scale * v for v in curve["trans_err_m"]], color=color, linewidth=1.2)
    ax_rot.plot(curve["time_s"], curve["rot_err_deg"], color=color, linewidth=1.2)
    ax_trans.set_ylabel("translation error (%s)" % unit)
    ax_rot.set_ylabel("rotation error (deg)")
    for ax, stats, s, u in ((ax_trans, trans_stats, scale, unit), (ax_rot, rot_stats, 1.0, "deg")):
        ax.set_xlabel("time (s)")
        ax.grid(True, alpha=0.3)
        ax.set_ylim(bottom=0)
        if stats:
            ax.set_title("ATE: RMSE %.3g %s, max %.3g %s" % (s * stats["rmse"], u, s * stats["max"], u), fontsize=10)


def save(fig, path):
    """Writes the PNG atomically (temporary file + rename)."""
    tmp = "%s.tmp.%d.png" % (path, os.getpid())
    try:
        fig.savefig(tmp, dpi=110, format="png", bbox_inches="tight")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
        plt.close(fig)


def plot(args):
    files = list(args.files)
    labels = list(args.labels or [])
    if len(labels) > len(files):
        raise PlotError("%d labels for %d files" % (len(labels), len(files)))
    labels += [os.path.basename(f) for f in files[len(labels):]]
    reference = args.reference
    segments = []
    if args.scene:
        segments = read_scene(os.path.join(args.scene, "scene.csv"))
        files.insert(0, os.path.join(args.scene, "gt.tum"))
        labels.insert(0, "ground truth")
        reference = True
    if not files:
        raise PlotError("no trajectory to draw (give FILE ... or --scene DIR)")

    curves = []
    color = 0
    for k, (path, label) in enumerate(zip(files, labels)):
        _, xyz = read_trajectory(path, args.format, args.kitti_frame_period)
        if k == 0 and reference:
            style = REFERENCE_STYLE
        else:
            style = dict(color=COLORS[color % len(COLORS)], linewidth=1.3)
            color += 1
        curves.append(("%s (path %s)" % (label, length_text(path_length(xyz))), xyz, style))

    errors = read_errors(args.errors) if args.errors else None
    rows = 2 if errors else 1
    fig, axes = plt.subplots(rows, 2, figsize=(13, 5.2 * rows + 0.6), squeeze=False,
                             gridspec_kw={"height_ratios": [1.6, 1] if errors else [1]})
    ax_plan, ax_side = axes[0]
    if segments:
        draw_segments(ax_plan, ax_side, segments)
    for label, xyz, style in curves:
        draw_curve(ax_plan, ax_side, xyz, label, style)
    label_views(ax_plan, ax_side)
    if errors:
        draw_errors(axes[1][0], axes[1][1], *errors, color=curves[-1][2]["color"])
    handles, names = ax_plan.get_legend_handles_labels()
    more_handles, more_names = marker_handles()
    fig.legend(handles + more_handles, names + more_names, loc="lower center", ncol=2, fontsize=9, frameon=False)
    title = args.title or ("Scene and camera path: " + args.scene if args.scene else "Trajectories")
    fig.suptitle(title, fontsize=11)
    legend_rows = (len(handles) + len(more_handles) + 1) // 2
    fig.tight_layout(rect=(0, min(0.3, 0.035 * legend_rows / rows + 0.02), 1, 0.97))
    save(fig, args.out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("files", nargs="*", metavar="FILE", help="TUM or KITTI trajectories")
    parser.add_argument("--out", "-o", required=True, help="PNG to write")
    parser.add_argument("--labels", nargs="+", help="one label per FILE (default: the file names)")
    parser.add_argument("--reference", action="store_true", help="the first FILE is the ground truth")
    parser.add_argument("--format", choices=("auto", "tum", "kitti"), default="auto", help="format of every FILE")
    parser.add_argument("--kitti-frame-period", type=float, default=0.1, help="seconds between KITTI poses")
    parser.add_argument("--errors", help="evaluate's JSON with its per-frame curve")
    parser.add_argument("--scene", help="a simulate output directory (scene.csv, gt.tum)")
    parser.add_argument("--title", help="figure title")
    args = parser.parse_args()
    if not args.out.endswith(".png"):
        parser.error("--out must name a .png file")
    try:
        plot(args)
    except PlotError as e:
        sys.stderr.write("plot_trajectory.py: error: %s\n" % e)
        sys.exit(1)


if __name__ == "__main__":
    main()
