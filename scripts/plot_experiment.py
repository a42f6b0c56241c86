#!/usr/bin/python3
"""Draws the PNG plots of one run_experiment output directory (docs/experiments.md).

    /usr/bin/python3 scripts/plot_experiment.py DIR [--only FILE.png ...] [--quiet]

Reads DIR/config.resolved.json (its "plots" list says what to draw), DIR/summary.csv,
DIR/curves.csv and DIR/raw/trajectories/, and writes each PNG into DIR atomically (temporary
file + rename). Plot kinds:

  sweep       error at the metrics frame vs the swept parameter: rotation and translation
              panels, one line per method (the paper's Fig. 4 and 5), the paper's reported
              values as black triangles with a caption comparing them with the reproduction
  grid        two swept parameters: x = the first, one panel per value of the second (one line
              per method) or one panel per method (one line per value of the second)
  curves      accumulated rotation (top) and translation (bottom) error vs frame number, one
              line per method (Fig. 6)
  trajectory  plan view (x-z) and side view (z-height) of one trial, one column per method
              against the ground truth, start (dot) and end (cross) in the method's colour
              (Figs. 11-12); ATE, largest error and, on a closed loop, the start-end gap
  methods     one row per method: mean, median and 95 % interval of the errors at every sweep
              point (the ablation tables)

Every figure has one legend, translations in mm, rates in %, and log axes labelled with plain
numbers. Lines show the plot's "statistic" over trials: the mean, the median, or both (median
solid, mean dotted).

Needs matplotlib (Debian: apt-get install python3-matplotlib; it is in /usr/bin/python3, which
is why run_experiment calls that interpreter).
"""

import argparse
import csv
import json
import math
import os
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_trajectory as trajectories  # noqa: E402 (exits with a message when matplotlib is missing)

plt = trajectories.plt
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402

MARKERS = ["*", "s", "^", "o", "D", "v", "P", "X", "<", ">"]
COLORS = trajectories.COLORS

# (CSV metric, panel name, unit, factor from the CSV's unit): translations are drawn in mm.
ROTATION = ("rot_err_deg", "Rotation error", "deg", 1.0)
TRANSLATION = ("trans_err_m", "Translation error", "mm", 1000.0)
PAPER_STYLE = dict(marker="v", color="black", markersize=10, linestyle="", zorder=6)


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


def format_value(v):
    """A sweep value as the CSV writes it (shortest form)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)


def is_rate(axis):
    """Rates (outliers.rate) are fractions in the configs and percentages on the plots."""
    return axis["parameter"].split(".")[-1].endswith("rate")


def axis_label(axis):
    return axis["label"] + (" (%)" if is_rate(axis) and "%" not in axis["label"] else "")


def value_text(axis, v):
    if is_rate(axis):
        return "%g %%" % (100.0 * float(v))
    return format_value(v)


def axis_positions(axis):
    """Numeric x positions of sweep values (rates in %), or categorical positions with tick labels."""
    values = axis["values"]
    try:
        scale = 100.0 if is_rate(axis) else 1.0
        return [scale * float(v) for v in values], None
    except (TypeError, ValueError):
        return list(range(len(values))), [format_value(v) for v in values]


def style(index):
    return dict(marker=MARKERS[index % len(MARKERS)], color=COLORS[index % len(COLORS)])


def frame_text(config):
    mf = config["metrics_frame"]
    return "the last frame" if mf == "last" else "frame %d" % (mf + 1)


def statistics(plot):
    """(CSV suffix, line style, legend note) of each statistic the plot draws."""
    return {"mean": [("_mean", "-", "mean")],
            "median": [("_median", "-", "median")],
            "both": [("_median", "-", "median"), ("_mean", ":", "mean")]}[plot.get("statistic", "mean")]


def statistic_text(plot, trials):
    text = {"mean": "mean", "median": "median", "both": "median (solid) and mean (dotted)"}[plot.get("statistic", "mean")]
    return "%s of %s trials" % (text, trials)


def plain_number(v, _=None):
    return "%g" % v


def readable_log_axis(axis):
    """Labels on a log axis at 1-2-5 steps (or decades over a wide range), as plain numbers."""
    lo, hi = axis.get_view_interval()
    if not (lo > 0 and hi > lo):
        return
    decades = math.log10(hi / lo)
    subs = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0) if decades < 1.2 else (1.0, 2.0, 5.0) if decades < 3.2 else (1.0,)
    axis.set_major_locator(LogLocator(base=10.0, subs=subs, numticks=12))
    axis.set_major_formatter(FuncFormatter(plain_number))
    axis.set_minor_formatter(NullFormatter())


def finish(fig, title, handles=(), labels=(), caption="", ncol=None):
    """Title, the figure's one legend under the panels, and a caption under the legend."""
    fig.suptitle(title, fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    bottom = 0.0
    if handles:
        legend = fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.0),
                            ncol=ncol or min(len(labels), 5), fontsize=9, frameon=False)
        fig.canvas.draw()
        bottom = legend.get_window_extent().transformed(fig.transFigure.inverted()).y0
    if caption:
        width = int(fig.get_figwidth() * 110 / 6.6)
        text = "\n".join(textwrap.fill(p, width) for p in caption.split("\n"))
        fig.text(0.01, bottom - 0.01, text, ha="left", va="top", fontsize=8.5)


def save(fig, path):
    trajectories.save(fig, path)


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

    def row(self, method, **fixed):
        """The summary row of `method` whose sweep columns equal `fixed` (parameter -> value text);
        a row of NaN when there is none."""
        for r in self.summary:
            if r["method"] == method and all(r[k] == v for k, v in fixed.items()):
                return r
        return {k: "nan" for k in self.summary[0]}

    def trackers(self):
        """The tracker names behind the methods, in order, without repeats."""
        names = []
        for m in self.config["methods"]:
            if m["name"] not in names:
                names.append(m["name"])
        return names

    def is_closed_loop(self):
        points = self.config.get("resolved", {}).get("points", [])
        return bool(points) and all("simulation" in p and p["simulation"]["motion"]["type"] == "loop" for p in points)


def draw_series(panels, xs, rows, label, st, plot):
    """One method (or sweep value) in every panel: panels = [(ax, metric spec)]."""
    for ax, (metric, _, _, factor) in panels:
        for k, (suffix, linestyle, _) in enumerate(statistics(plot)):
            y = [factor * number(r[metric + suffix]) for r in rows]
            if plot["yscale"] == "log":
                y = [v if v > 0 else math.nan for v in y]
            ax.plot(xs, y, label=label if k == 0 else None, linestyle=linestyle,
                    markersize=(8 if st["marker"] == "*" else 6) if k == 0 else 0, linewidth=1.5 if k == 0 else 1.2, **st)
        if plot["band"]:
            lo = [factor * number(r[metric + "_p2_5"]) for r in rows]
            hi = [factor * number(r[metric + "_p97_5"]) for r in rows]
            if plot["yscale"] == "log":
                lo = [v if v > 0 else math.nan for v in lo]
            ax.fill_between(xs, lo, hi, color=st["color"], alpha=0.12, linewidth=0)


def label_panel(ax, spec, plot, where):
    metric, name, unit, _ = spec
    ax.set_ylabel("%s at %s (%s)" % (name, where, unit))
    ax.set_yscale(plot["yscale"])
    ax.grid(True, which="major", alpha=0.3)
    if plot["yscale"] == "linear":
        ax.set_ylim(bottom=0)


def statistic_handles(plot):
    """Legend entries for the line styles when the plot draws two statistics."""
    stats = statistics(plot)
    if len(stats) < 2:
        return [], []
    return ([plt.Line2D([], [], color="0.3", linestyle=ls) for _, ls, _ in stats], [note for _, _, note in stats])


def band_handles(plot):
    if not plot["band"]:
        return [], []
    return [plt.Rectangle((0, 0), 1, 1, color="0.5", alpha=0.25)], ["95 % of trials (shaded)"]


def paper_caption(exp, plot, axis):
    """The paper's values against the reproduction at the same sweep point, one sentence each."""
    sentences = []
    for pv in plot.get("paper", []):
        bound = "< " if pv["upper_bound"] else ""
        reported = []
        if pv["rot_err_deg"] >= 0:
            reported.append("%s%g°" % (bound, pv["rot_err_deg"]))
        if pv["trans_err_m"] >= 0:
            reported.append("%s%g mm" % (bound, 1000.0 * pv["trans_err_m"]))
        here = []
        for method in exp.methods:
            r = exp.row(method, **{axis["parameter"]: format_value(pv["x"])})
            rot, trans = number(r["rot_err_deg_mean"]), 1000.0 * number(r["trans_err_m_mean"])
            worse = []
            if pv["rot_err_deg"] >= 0 and not rot <= pv["rot_err_deg"]:
                worse.append("rotation")
            if pv["trans_err_m"] >= 0 and not trans <= 1000.0 * pv["trans_err_m"]:
                worse.append("translation")
            verdict = "within the paper's figure" if not worse else " and ".join(worse) + " above it"
            here.append("%s %.3g° / %.3g mm (%s)" % (method, rot, trans, verdict))
        where = axis["label"][:1].lower() + axis["label"][1:]
        sentences.append("%s reports %s at %s = %s (black triangles). Here, mean of %s trials: %s." % (
            pv["label"], " and ".join(reported), where, value_text(axis, pv["x"]),
            exp.config["trials"], "; ".join(here)))
    return " ".join(sentences)


def plot_sweep(exp, plot):
    axis = exp.axes[0]
    xs, ticks = axis_positions(axis)
    specs = (ROTATION, TRANSLATION)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    panels = list(zip(axes, specs))
    for i, method in enumerate(exp.methods):
        rows = [exp.row(method, **{axis["parameter"]: format_value(v)}) for v in axis["values"]]
        draw_series(panels, xs, rows, method, style(i), plot)
    handles, labels = axes[0].get_legend_handles_labels()
    for pv in plot.get("paper", []):
        x = (100.0 if is_rate(axis) else 1.0) * pv["x"]
        for ax, (metric, _, unit, factor) in panels:
            value = pv[metric]
            if value >= 0:
                ax.plot([x], [factor * value], **PAPER_STYLE)
                ax.annotate("paper %s%g%s" % ("< " if pv["upper_bound"] else "", factor * value,
                                              "°" if unit == "deg" else " " + unit),
                            (x, factor * value), textcoords="offset points", xytext=(-8, 8), ha="right", fontsize=8.5)
    if plot.get("paper"):
        handles.append(plt.Line2D([], [], **PAPER_STYLE))
        labels.append("the paper's reported value (upper bound)")
    for ax, spec in panels:
        label_panel(ax, spec, plot, frame_text(exp.config))
        ax.set_xlabel(axis_label(axis))
        if ticks:
            ax.set_xticks(xs)
            ax.set_xticklabels(ticks)
        if plot["yscale"] == "log":
            readable_log_axis(ax.yaxis)
    more = [statistic_handles(plot), band_handles(plot)]
    for h, l in more:
        handles += h
        labels += l
    caption = "\n".join(c for c in (paper_caption(exp, plot, axis), plot.get("caption", "")) if c)
    title = "%s; %s" % (plot["title"], statistic_text(plot, exp.config["trials"]))
    finish(fig, title, handles, labels, caption)
    save(fig, os.path.join(exp.dir, plot["file"]))


def plot_grid(exp, plot):
    x_axis, p_axis = exp.axes
    xs, ticks = axis_positions(x_axis)
    if plot["lines"] == "methods":
        panels = [("%s = %s" % (p_axis["label"], value_text(p_axis, v)), v) for v in p_axis["values"]]
    else:
        panels = [(m, m) for m in exp.methods]
    n = len(panels)
    fig, axes = plt.subplots(2, n, figsize=(3.6 * n + 1.0, 7.4), squeeze=False, sharex=True, sharey="row")
    for c, (title, key) in enumerate(panels):
        column = [(axes[0][c], ROTATION), (axes[1][c], TRANSLATION)]
        if plot["lines"] == "methods":
            for i, method in enumerate(exp.methods):
                rows = [exp.row(method, **{x_axis["parameter"]: format_value(x), p_axis["parameter"]: format_value(key)})
                        for x in x_axis["values"]]
                draw_series(column, xs, rows, method, style(i), plot)
        else:
            for i, v in enumerate(p_axis["values"]):
                rows = [exp.row(key, **{x_axis["parameter"]: format_value(x), p_axis["parameter"]: format_value(v)})
                        for x in x_axis["values"]]
                draw_series(column, xs, rows, "%s = %s" % (p_axis["label"], value_text(p_axis, v)), style(i), plot)
        for ax, spec in column:
            label_panel(ax, spec, plot, frame_text(exp.config))
        axes[0][c].set_title(title, fontsize=10)
        axes[1][c].set_xlabel(axis_label(x_axis))
        if c > 0:
            axes[0][c].set_ylabel("")
            axes[1][c].set_ylabel("")
        if ticks:
            axes[1][c].set_xticks(xs)
            axes[1][c].set_xticklabels(ticks)
    if plot["yscale"] == "log":
        for r in range(2):
            readable_log_axis(axes[r][0].yaxis)  # shared by the row
    handles, labels = axes[0][0].get_legend_handles_labels()
    for h, l in (statistic_handles(plot), band_handles(plot)):
        handles += h
        labels += l
    title = "%s; %s" % (plot["title"], statistic_text(plot, exp.config["trials"]))
    finish(fig, title, handles, labels, plot.get("caption", ""), ncol=min(len(labels), 5))
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
                title = ", ".join("%s = %s" % (a["label"], value_text(a, g[0][a["parameter"]])) for a in exp.axes)
            frames = [int(r["frame"]) for r in g]
            st = style(i)
            every = max(1, len(frames) // 12)
            for ax, (metric, _, _, factor) in ((ax_rot, ROTATION), (ax_trans, TRANSLATION)):
                for k, (suffix, linestyle, _) in enumerate(statistics(plot)):
                    y = [factor * number(r[metric + suffix]) for r in g]
                    if plot["yscale"] == "log":  # frame 0 is exact (error 0): nothing to draw on a log axis
                        y = [v if v > 0 else math.nan for v in y]
                    ax.plot(frames, y, label=method if k == 0 else None, linestyle=linestyle, markevery=every,
                            linewidth=1.5 if k == 0 else 1.2,
                            markersize=(8 if st["marker"] == "*" else 5) if k == 0 else 0, **st)
        ax_rot.set_ylabel("Accumulated rotation error (deg)")
        ax_trans.set_ylabel("Accumulated translation error (mm)")
        ax_trans.set_xlabel("Frame number")
        for ax in (ax_rot, ax_trans):
            ax.set_yscale(plot["yscale"])
            ax.grid(True, alpha=0.3)
            if plot["yscale"] == "linear":
                ax.set_ylim(bottom=0)
            else:
                readable_log_axis(ax.yaxis)
            ax.set_xlim(left=0)
        if title:
            ax_rot.set_title(title, fontsize=10)
    handles, labels = axes[0][0].get_legend_handles_labels()
    h, l = statistic_handles(plot)
    title = "%s; %s" % (plot["title"], statistic_text(plot, exp.config["trials"]))
    finish(fig, title, handles + h, labels + l, plot.get("caption", ""))
    save(fig, os.path.join(exp.dir, plot["file"]))


def plot_trajectory(exp, plot):
    """One column per method, each against the ground truth and scaled to itself: a method that
    diverges gets its own scale and does not squeeze the others."""
    tdir = os.path.join(exp.dir, "raw", "trajectories")
    index = read_csv(os.path.join(tdir, "index.csv"))
    trial = str(plot["trial"])
    entries = [r for r in index if r["trial"] == trial and r["point"] == "0"]
    if not entries:
        fail("%s: no trajectory of trial %s at sweep point 0" % (os.path.join(tdir, "index.csv"), trial))
    trials = {(r["method"], r["point"], r["trial"]): r for r in read_csv(os.path.join(exp.dir, "raw", "trials.csv"))}

    def read(name):
        try:
            return trajectories.read_trajectory(os.path.join(tdir, name), "tum")[1]
        except trajectories.PlotError as e:
            fail(str(e))

    gt = read(entries[0]["ground_truth"])
    closed = exp.is_closed_loop()
    by_method = {r["method"]: r for r in entries}
    methods = [m for m in exp.methods if m in by_method]
    n = len(methods)
    fig, axes = plt.subplots(2, n, figsize=(4.6 * n + 0.6, 9.4), squeeze=False)
    for c, method in enumerate(methods):
        ax_plan, ax_side = axes[0][c], axes[1][c]
        st = dict(color=COLORS[exp.methods.index(method) % len(COLORS)], linewidth=1.3)
        trajectories.draw_curve(ax_plan, ax_side, gt, "ground truth", trajectories.REFERENCE_STYLE)
        trajectories.draw_curve(ax_plan, ax_side, read(by_method[method]["estimate"]), method, st)
        trajectories.label_views(ax_plan, ax_side)
        t = trials.get((method, "0", trial), {})
        distance = trajectories.distance_text
        lines = ["ATE %s RMSE, largest %s" % (distance(number(t.get("ate_trans_m"))),
                                             distance(number(t.get("max_trans_err_m"))))]
        if closed:
            lines.append("start-end gap %s (%s %% of the path)" % (distance(number(t.get("end_gap_m"))),
                                                                   "%.2g" % number(t.get("drift_pct"))
                                                                   if number(t.get("drift_pct")) < 100
                                                                   else "%.0f" % number(t.get("drift_pct"))))
        ax_plan.set_title(method + "\n" + "\n".join(lines), fontsize=9.5)
    handles = [plt.Line2D([], [], **trajectories.REFERENCE_STYLE)]
    labels = ["ground truth (path %s)" % trajectories.length_text(trajectories.path_length(gt))]
    for method in methods:
        handles.append(plt.Line2D([], [], color=COLORS[exp.methods.index(method) % len(COLORS)], linewidth=1.3))
        labels.append(method)
    h, l = trajectories.marker_handles()
    caption = plot.get("caption", "")
    if not closed:
        caption = ("The path is open: the start-end gap is not a drift measure and is not shown. " + caption).strip()
    finish(fig, plot["title"], handles + h, labels + l, caption, ncol=3)
    save(fig, os.path.join(exp.dir, plot["file"]))


def plot_methods(exp, plot):
    """Rows = methods, columns = rotation and translation: median (dot), mean (diamond) and 95 %
    interval (bar) over trials at each sweep point (offset vertically, one colour each)."""
    points = [{}]
    point_labels = [""]
    for axis in exp.axes[:2]:
        points = [dict(p, **{axis["parameter"]: format_value(v)}) for p in points for v in axis["values"]]
        point_labels = [(l + ", " if l else "") + "%s = %s" % (axis["label"], value_text(axis, v))
                        for l in point_labels for v in axis["values"]]
    n_methods, n_points = len(exp.methods), len(points)
    fig, axes = plt.subplots(1, 2, figsize=(13, 1.0 + 0.38 * n_methods * max(1, n_points) ** 0.5 + 1.2), sharey=True)
    offsets = [0.0] if n_points == 1 else [0.36 * (k / (n_points - 1) - 0.5) for k in range(n_points)]
    for ax, (metric, name, unit, factor) in zip(axes, (ROTATION, TRANSLATION)):
        for k, fixed in enumerate(points):
            color = COLORS[k % len(COLORS)] if n_points > 1 else COLORS[0]
            for m, method in enumerate(exp.methods):
                r = exp.row(method, **fixed)
                y = m + offsets[k]
                lo, hi = factor * number(r[metric + "_p2_5"]), factor * number(r[metric + "_p97_5"])
                ax.plot([lo, hi], [y, y], color=color, linewidth=1.6, alpha=0.6)
                ax.plot([factor * number(r[metric + "_median"])], [y], "o", color=color, markersize=5.5)
                ax.plot([factor * number(r[metric + "_mean"])], [y], "D", color=color, markersize=5.5,
                        markerfacecolor="white", markeredgewidth=1.4)
        for pv in plot.get("paper", []):
            if pv[metric] >= 0:
                ax.axvline(factor * pv[metric], color="black", linestyle="--", linewidth=1.1)
                ax.annotate("paper %s%g%s" % ("< " if pv["upper_bound"] else "", factor * pv[metric],
                                              "°" if unit == "deg" else " " + unit),
                            (factor * pv[metric], 1.0), xycoords=("data", "axes fraction"), xytext=(-3, -12),
                            textcoords="offset points", ha="right", fontsize=8.5)
        ax.set_xscale(plot["yscale"])
        if plot["yscale"] == "log":
            readable_log_axis(ax.xaxis)
        ax.set_xlabel("%s at %s (%s)" % (name, frame_text(exp.config), unit))
        ax.grid(True, axis="x", which="major", alpha=0.3)
    axes[0].set_yticks(range(n_methods))
    axes[0].set_yticklabels(exp.methods, fontsize=9)
    axes[0].set_ylim(n_methods - 0.5, -1.0 if plot.get("paper") else -0.5)  # room for the paper's label
    handles = [plt.Line2D([], [], marker="o", color="0.3", linestyle=""),
               plt.Line2D([], [], marker="D", color="0.3", markerfacecolor="white", linestyle=""),
               plt.Line2D([], [], color="0.3", linewidth=1.6, alpha=0.6)]
    labels = ["median", "mean", "95 % of trials"]
    if plot.get("paper"):
        handles.append(plt.Line2D([], [], color="black", linestyle="--", linewidth=1.1))
        labels.append(plot["paper"][0]["label"] + ": reported value")
    if n_points > 1:
        for k, text in enumerate(point_labels):
            handles.append(plt.Rectangle((0, 0), 1, 1, color=COLORS[k % len(COLORS)]))
            labels.append(text)
    trackers = exp.trackers()
    title = "%s\n(tracker%s: %s; %s trials)" % (plot["title"], "s" if len(trackers) > 1 else "", ", ".join(trackers),
                                                 exp.config["trials"])
    finish(fig, title, handles, labels, plot.get("caption", ""), ncol=min(len(labels), 6))
    save(fig, os.path.join(exp.dir, plot["file"]))


DRAW = {"sweep": plot_sweep, "grid": plot_grid, "curves": plot_curves, "trajectory": plot_trajectory,
        "methods": plot_methods}


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
