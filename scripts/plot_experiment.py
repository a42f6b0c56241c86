#!/usr/bin/python3
"""Draws the PNG plots of one run_experiment output directory (docs/experiments.md).

    /usr/bin/python3 scripts/plot_experiment.py DIR [--only FILE.png ...] [--quiet]

Reads DIR/config.resolved.json (its "plots" list says what to draw), DIR/summary.csv,
DIR/curves.csv and DIR/raw/trajectories/, and writes each PNG into DIR atomically (temporary
file + rename). Plot kinds:

  sweep       error at the metrics frame vs the swept parameter: rotation and translation
              panels, one line per method (the paper's Fig. 4 and 5)
  grid        two swept parameters: x = the first, one panel per value of the second (one line
              per method) or one panel per method (one line per value of the second)
  curves      mean accumulated rotation (top) and translation (bottom) error vs frame number,
              one line per method (Fig. 6)
  trajectory  plan view (x-z) and side view (z-height) of the ground truth and every method for
              one trial, start (red dot) and end (blue cross) markers (Figs. 11-12)

Needs matplotlib (Debian: apt-get install python3-matplotlib; it is in /usr/bin/python3, which
is why run_experiment calls that interpreter).
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
except ImportError:
    sys.stderr.write(
        "plot_experiment.py: error: matplotlib is not available for %s "
        "(Debian: apt-get install python3-matplotlib, then run with /usr/bin/python3)\n" % sys.executable
    )
    sys.exit(1)

MARKERS = ["*", "s", "^", "o", "D", "v", "P", "X", "<", ">"]
COLORS = plt.rcParams["axes.prop_cycle"].by_key()["color"]


def fail(message):
    sys.stderr.write("plot_experiment.py: error: %s\n" % message)
    sys.exit(1)


def read_csv(path):
    try:
        with open(path, newline="") as f:
            return list(csv.DictReader(f))
    except OSError as e:
        fail("%s: %s" % (path, e.strerror))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def save(fig, path):
    tmp = "%s.tmp.%d" % (path, os.getpid())
    try:
        fig.savefig(tmp, dpi=110, format="png", bbox_inches="tight")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
        plt.close(fig)


def format_value(v):
    """A sweep value as the CSV writes it (shortest form)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)


def axis_positions(values):
    """Numeric x positions of sweep values, or categorical positions with tick labels."""
    try:
        return [float(v) for v in values], None
    except (TypeError, ValueError):
        return list(range(len(values))), [format_value(v) for v in values]


def style(index):
    return dict(marker=MARKERS[index % len(MARKERS)], color=COLORS[index % len(COLORS)])


def frame_text(config):
    mf = config["metrics_frame"]
    return "the last frame" if mf == "last" else "frame %d" % (mf + 1)


class Experiment:
    def __init__(self, directory):
        self.dir = directory
        path = os.path.join(directory, "config.resolved.json")
        try:
            with open(path) as f:
                self.config = json.load(f)
        except OSError as e:
            fail("%s: %s" % (path, e.strerror))
        self.methods = [m["label"] for m in self.config["methods"]]
        self.axes = self.config["sweep"]
        self._summary = None

    @property
    def summary(self):
        if self._summary is None:
            self._summary = read_csv(os.path.join(self.dir, "summary.csv"))
        return self._summary

    def rows(self, method, **fixed):
        """Summary rows of `method` whose sweep columns equal `fixed` (parameter -> value text)."""
        out = []
        for r in self.summary:
            if r["method"] != method:
                continue
            if all(r[k] == v for k, v in fixed.items()):
                out.append(r)
        return out


def error_panels(ax_rot, ax_trans, plot, xlabel, frame):
    ax_rot.set_ylabel("Rotation error at %s (deg)" % frame)
    ax_trans.set_ylabel("Translation error at %s (m)" % frame)
    for ax in (ax_rot, ax_trans):
        ax.set_xlabel(xlabel)
        ax.set_yscale(plot["yscale"])
        ax.grid(True, which="major", alpha=0.3)
        if plot["yscale"] == "linear":
            ax.set_ylim(bottom=0)


def draw_lines(ax_rot, ax_trans, series, plot):
    """series: list of (label, style, x positions, rows)."""
    for label, st, xs, rows in series:
        for ax, metric in ((ax_rot, "rot_err_deg"), (ax_trans, "trans_err_m")):
            y = [number(r[metric + "_mean"]) for r in rows]
            if plot["yscale"] == "log":
                y = [v if v > 0 else math.nan for v in y]
            ax.plot(xs, y, label=label, markersize=8 if st["marker"] == "*" else 6, linewidth=1.5, **st)
            if plot["band"]:
                lo = [number(r[metric + "_p2_5"]) for r in rows]
                hi = [number(r[metric + "_p97_5"]) for r in rows]
                ax.fill_between(xs, lo, hi, color=st["color"], alpha=0.12, linewidth=0)


def plot_sweep(exp, plot):
    axis = exp.axes[0]
    xs, ticks = axis_positions(axis["values"])
    fig, (ax_rot, ax_trans) = plt.subplots(1, 2, figsize=(12, 4.6))
    series = []
    for i, method in enumerate(exp.methods):
        rows = []
        for v in axis["values"]:
            match = exp.rows(method, **{axis["parameter"]: format_value(v)})
            rows.append(match[0] if match else {})
        rows = [r if r else {k: "nan" for k in exp.summary[0]} for r in rows]
        series.append((method, style(i), xs, rows))
    draw_lines(ax_rot, ax_trans, series, plot)
    error_panels(ax_rot, ax_trans, plot, axis["label"], frame_text(exp.config))
    if ticks:
        for ax in (ax_rot, ax_trans):
            ax.set_xticks(xs)
            ax.set_xticklabels(ticks)
    ax_rot.legend(fontsize=9)
    trials = exp.config["trials"]
    fig.suptitle(plot["title"] + ("" if "trial" in plot["title"] else " (%d trials, mean)" % trials), fontsize=11)
    fig.tight_layout()
    save(fig, os.path.join(exp.dir, plot["file"]))


def plot_grid(exp, plot):
    x_axis, p_axis = exp.axes
    xs, ticks = axis_positions(x_axis["values"])
    if plot["lines"] == "methods":
        panels = [(p_axis["label"] + " = " + format_value(v), v) for v in p_axis["values"]]
    else:
        panels = [(m, m) for m in exp.methods]
    n = len(panels)
    fig, axes = plt.subplots(2, n, figsize=(3.6 * n + 1.0, 7.2), squeeze=False, sharex=True, sharey="row")
    for c, (title, key) in enumerate(panels):
        series = []
        if plot["lines"] == "methods":
            for i, method in enumerate(exp.methods):
                rows = [exp.rows(method, **{x_axis["parameter"]: format_value(x), p_axis["parameter"]: format_value(key)})
                        for x in x_axis["values"]]
                series.append((method, style(i), xs, [r[0] if r else {} for r in rows]))
        else:
            for i, v in enumerate(p_axis["values"]):
                rows = [exp.rows(key, **{x_axis["parameter"]: format_value(x), p_axis["parameter"]: format_value(v)})
                        for x in x_axis["values"]]
                series.append((p_axis["label"] + " = " + format_value(v), style(i), xs, [r[0] if r else {} for r in rows]))
        blank = {k: "nan" for k in exp.summary[0]}
        series = [(label, st, x, [r if r else blank for r in rows]) for label, st, x, rows in series]
        draw_lines(axes[0][c], axes[1][c], series, plot)
        error_panels(axes[0][c], axes[1][c], plot, x_axis["label"], frame_text(exp.config))
        axes[0][c].set_title(title, fontsize=10)
        if c > 0:
            axes[0][c].set_ylabel("")
            axes[1][c].set_ylabel("")
        axes[0][c].set_xlabel("")
        if ticks:
            axes[1][c].set_xticks(xs)
            axes[1][c].set_xticklabels(ticks)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 5), fontsize=9, frameon=False)
    fig.suptitle(plot["title"], fontsize=11)
    fig.tight_layout(rect=(0, 0.06, 1, 0.97))
    save(fig, os.path.join(exp.dir, plot["file"]))


def plot_curves(exp, plot):
    """One column per sweep point (a single column without a sweep); rotation on top."""
    rows = read_csv(os.path.join(exp.dir, "curves.csv"))
    groups = {}
    for r in rows:
        groups.setdefault((r["method"], r["point"]), []).append(r)
    points = sorted({int(p) for _, p in groups})
    n = len(points)
    fig, axes = plt.subplots(2, n, figsize=(8.5 if n == 1 else 6.2 * n, 7.5), squeeze=False, sharex=True)
    for c, p in enumerate(points):
        ax_rot, ax_trans = axes[0][c], axes[1][c]
        title = None
        for i, method in enumerate(exp.methods):
            g = groups.get((method, str(p)))
            if not g:
                continue
            if exp.axes:
                title = ", ".join("%s = %s" % (a["label"], g[0][a["parameter"]]) for a in exp.axes)
            frames = [int(r["frame"]) for r in g]
            st = style(i)
            every = max(1, len(frames) // 12)
            for ax, metric in ((ax_rot, "rot_err_deg_mean"), (ax_trans, "trans_err_m_mean")):
                y = [number(r[metric]) for r in g]
                if plot["yscale"] == "log":  # frame 0 is exact (error 0): nothing to draw on a log axis
                    y = [v if v > 0 else math.nan for v in y]
                ax.plot(frames, y, label="%s (%s trials)" % (method, g[0]["trials"]),
                        markevery=every, linewidth=1.5, markersize=8 if st["marker"] == "*" else 5, **st)
        ax_rot.set_ylabel("Mean accumulated rotation error (deg)")
        ax_trans.set_ylabel("Mean accumulated translation error (m)")
        ax_trans.set_xlabel("Frame number")
        for ax in (ax_rot, ax_trans):
            ax.set_yscale(plot["yscale"])
            ax.grid(True, alpha=0.3)
            if plot["yscale"] == "linear":
                ax.set_ylim(bottom=0)
            ax.set_xlim(left=0)
        ax_rot.legend(fontsize=9)
        if title:
            ax_rot.set_title(title, fontsize=10)
    fig.suptitle(plot["title"], fontsize=11)
    fig.tight_layout()
    save(fig, os.path.join(exp.dir, plot["file"]))


def read_tum(path):
    xyz = []
    try:
        with open(path) as f:
            for line in f:
                s = line.strip()
                if not s or s.startswith("#"):
                    continue
                v = s.split()
                xyz.append((float(v[1]), float(v[2]), float(v[3])))
    except OSError as e:
        fail("%s: %s" % (path, e.strerror))
    return xyz


def plot_trajectory(exp, plot):
    tdir = os.path.join(exp.dir, "raw", "trajectories")
    index = read_csv(os.path.join(tdir, "index.csv"))
    trial = str(plot["trial"])
    entries = [r for r in index if r["trial"] == trial and r["point"] == "0"]
    if not entries:
        fail("%s: no trajectory of trial %s at sweep point 0" % (os.path.join(tdir, "index.csv"), trial))
    trials = {(r["method"], r["point"], r["trial"]): r for r in read_csv(os.path.join(exp.dir, "raw", "trials.csv"))}
    gt = read_tum(os.path.join(tdir, entries[0]["ground_truth"]))
    path_length = sum(math.dist(gt[k], gt[k - 1]) for k in range(1, len(gt)))
    curves = [("ground truth (path %.2f m)" % path_length, gt, dict(color="black", linestyle="--", linewidth=1.2))]
    by_method = {r["method"]: r for r in entries}
    for i, method in enumerate(exp.methods):
        if method not in by_method:
            continue
        est = read_tum(os.path.join(tdir, by_method[method]["estimate"]))
        t = trials.get((method, "0", trial), {})
        # The start-end gap only says where the loop closed; ATE and the maximum error say how far
        # off the track was along the way (docs/experiments.md).
        pct = lambda key: 100.0 * number(t.get(key)) / path_length if path_length > 0 else float("nan")
        label = "%s: ATE %.3f m (%.1f %%), max %.3f m (%.1f %%), start-end gap %.3f m (%.1f %%)" % (
            method, number(t.get("ate_trans_m")), pct("ate_trans_m"), number(t.get("max_trans_err_m")),
            pct("max_trans_err_m"), number(t.get("end_gap_m")), number(t.get("drift_pct")))
        curves.append((label, est, dict(color=COLORS[i % len(COLORS)], linewidth=1.3)))

    # Views: plan = (x, z), side = (z, height = -y; the camera's y points down).
    def views(xyz):
        return ([p[0] for p in xyz], [p[2] for p in xyz]), ([p[2] for p in xyz], [-p[1] for p in xyz])

    gt_views = views(gt)
    # When an estimate wanders far beyond the ground truth, a second row zooms on the ground truth.
    def box(view, margin):
        a, b = view
        span = max(max(a) - min(a), max(b) - min(b), 0.05)
        m = margin * span
        return (min(a) - m, max(a) + m), (min(b) - m, max(b) + m)

    zoom_boxes = [box(v, 0.25) for v in gt_views]
    far_boxes = [box(v, 1.0) for v in gt_views]
    needs_zoom = False
    for _, xyz, _ in curves[1:]:
        for view, ((a0, a1), (b0, b1)) in zip(views(xyz), far_boxes):
            a, b = view
            if min(a) < a0 or max(a) > a1 or min(b) < b0 or max(b) > b1:
                needs_zoom = True
    rows = 2 if needs_zoom else 1
    fig, axes = plt.subplots(rows, 2, figsize=(13, 5.6 * rows + 0.8), squeeze=False)
    for r in range(rows):
        ax_plan, ax_side = axes[r]
        for label, xyz, st in curves:
            for ax, (a, b) in zip((ax_plan, ax_side), views(xyz)):
                ax.plot(a, b, label=label, **st)
                ax.plot(a[0], b[0], "o", color="red", markersize=6, zorder=5)
                ax.plot(a[-1], b[-1], "x", color="blue", markersize=8, markeredgewidth=2, zorder=5)
        suffix = "" if r == 0 else " (zoomed on the ground truth)"
        ax_plan.set_title("Plan view" + suffix)
        ax_side.set_title("Side view" + suffix)
        ax_plan.set_xlabel("x, right (m)")
        ax_plan.set_ylabel("z, forward (m)")
        ax_side.set_xlabel("z, forward (m)")
        ax_side.set_ylabel("height, -y (m)")
        for c, ax in enumerate((ax_plan, ax_side)):
            ax.grid(True, alpha=0.3)
            if r == 1:
                (a0, a1), (b0, b1) = zoom_boxes[c]
                ax.set_xlim(a0, a1)
                ax.set_ylim(b0, b1)
                ax.set_aspect("equal", adjustable="box")
            else:
                ax.set_aspect("equal", adjustable="datalim")
    handles, labels = axes[0][0].get_legend_handles_labels()
    handles += [plt.Line2D([], [], marker="o", color="red", linestyle=""),
                plt.Line2D([], [], marker="x", color="blue", linestyle="", markeredgewidth=2)]
    labels += ["start", "end"]
    fig.legend(handles, labels, loc="lower center", ncol=2, fontsize=9, frameon=False)
    fig.suptitle(plot["title"], fontsize=11)
    fig.tight_layout(rect=(0, 0.1 / rows, 1, 0.97))
    save(fig, os.path.join(exp.dir, plot["file"]))


DRAW = {"sweep": plot_sweep, "grid": plot_grid, "curves": plot_curves, "trajectory": plot_trajectory}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dir", help="a run_experiment output directory")
    parser.add_argument("--only", nargs="*", default=None, help="draw only these PNG files")
    parser.add_argument("--quiet", action="store_true", help="do not list the files written")
    args = parser.parse_args()
    exp = Experiment(args.dir)
    for plot in exp.config.get("plots", []):
        if args.only and plot["file"] not in args.only:
            continue
        DRAW[plot["kind"]](exp, plot)
        if not args.quiet:
            print("plot_experiment.py: wrote %s" % os.path.join(args.dir, plot["file"]))


if __name__ == "__main__":
    main()
