#!/usr/bin/python3
"""Fills the generated blocks of README.md from results/: every result table and number the
README quotes comes from the committed summaries, so the two cannot disagree.

    scripts/update_readme.py [--check] [--readme README.md] [--results results/]

A block is `<!-- generated:NAME -->...<!-- /generated -->`, inline in a sentence or around a
table; its content is replaced by what GENERATORS[NAME] makes of results/. Run it after
regenerating results (`run_experiment ...`, `bench_table1 --out results/table1`,
`measure_frontend --out results/frontend`). With --check it writes nothing and exits with 1 and a
diff when README.md differs from what the results give (the CTest test readme_results_test). Methods are read from the summaries, so a tracker added to
the registry appears in the tables once its results exist. Python 3 standard library only.
"""

import argparse
import csv
import difflib
import json
import os
import re
import sys

BLOCK = re.compile(r"(<!-- generated:([a-z0-9_]+) -->)(.*?)(<!-- /generated -->)", re.S)


class ResultsError(Exception):
    """A result the README needs is missing; the message names the file."""


def sig(value, digits=3):
    """`value` with `digits` significant digits, plain notation down to 1e-4."""
    if value != value:
        return "nan"
    if value != 0 and abs(value) < 1e-4:
        mantissa, exponent = ("%.*e" % (digits - 2 if digits > 1 else 0, value)).split("e")
        return "%se-%d" % (mantissa, -int(exponent))
    if abs(value) >= 10 ** digits:
        return "%d" % round(value)
    return "%.*g" % (digits, value)


def deg(value):
    return sig(value) + "°"


def mm(value_m):
    """Millimetres below a metre, metres above (a diverged run)."""
    return sig(1000.0 * value_m) + " mm" if abs(value_m) < 1.0 else sig(value_m) + " m"


class Results:
    def __init__(self, root):
        self.root = root
        self._cache = {}

    def path(self, *parts):
        return os.path.join(self.root, *parts)

    def summary(self, experiment):
        """Rows of results/<experiment>/summary.csv, numbers as floats where they parse."""
        if experiment not in self._cache:
            path = self.path(experiment, "summary.csv")
            try:
                with open(path, newline="") as f:
                    rows = list(csv.DictReader(f))
            except OSError as e:
                raise ResultsError("%s: %s" % (path, e.strerror))
            if not rows:
                raise ResultsError("%s: no rows" % path)
            self._cache[experiment] = (path, rows)
        return self._cache[experiment][1]

    def methods(self, experiment):
        """Methods in the order of the summary (the config's order)."""
        names = []
        for r in self.summary(experiment):
            if r["method"] not in names:
                names.append(r["method"])
        return names

    def row(self, experiment, method, **fixed):
        for r in self.summary(experiment):
            if r["method"] == method and all(float(r[k]) == float(v) if is_number(v) else r[k] == v
                                              for k, v in fixed.items()):
                return r
        raise ResultsError("%s: no row for method '%s' at %s" % (self._cache[experiment][0], method, fixed or "the only point"))

    def value(self, experiment, method, column, **fixed):
        r = self.row(experiment, method, **fixed)
        if column not in r:
            raise ResultsError("%s: no column '%s'" % (self._cache[experiment][0], column))
        return float(r[column])

    def values(self, experiment, parameter):
        """The distinct values of a sweep column, in order of appearance, as floats."""
        out = []
        for r in self.summary(experiment):
            v = float(r[parameter])
            if v not in out:
                out.append(v)
        return out

    def json(self, *parts):
        path = self.path(*parts)
        try:
            with open(path) as f:
                return json.load(f)
        except OSError as e:
            raise ResultsError("%s: %s" % (path, e.strerror))

    def markdown_rows(self, *parts, table=0):
        """(path, rows) of a file's Markdown table (the first, or the table-th counting from 0),
        each row a dict by column title."""
        path = self.path(*parts)
        tables = [[]]
        try:
            with open(path, encoding="utf-8") as f:
                for l in f:
                    if l.strip().startswith("|"):
                        tables[-1].append(l.strip())
                    elif tables[-1]:
                        tables.append([])  # a table ended; the next has its own columns
        except OSError as e:
            raise ResultsError("%s: %s" % (path, e.strerror))
        lines = tables[table] if table < len(tables) else []
        cells = [[c.strip() for c in l.strip("|").split("|")] for l in lines]
        if len(cells) < 3:
            raise ResultsError("%s: no Markdown table%s" % (path, " %d (counting from 1)" % (table + 1) if table else ""))
        return path, [dict(zip(cells[0], row)) for row in cells[2:]]


def is_number(v):
    return isinstance(v, (int, float))


# The paper's values (Lee et al. 2015, Sec. 5.1 and Table 1), quoted beside the reproduction.
PAPER_FIG4 = (0.4, 0.010)  # deg, m at +-2.5 px (upper bounds)
PAPER_FIG5 = (0.03, 0.0015)  # deg, m at 200 px focal error (upper bounds)
DEFAULT = "trifocal_line_ekf"
POINTS = "yu_point_ekf"
FAITHFUL = "trifocal_line_ekf (paper preset)"


def fig4_table(r):
    noise = max(r.values("noise_sweep", "noise.endpoint_px"))
    lines = ["| at ±%s px | rotation | translation |" % sig(noise), "|---|---:|---:|",
             "| paper, trifocal-line EKF (upper bound) | < %s | < %s |" % (deg(PAPER_FIG4[0]), mm(PAPER_FIG4[1]))]
    for m in r.methods("noise_sweep"):
        lines.append("| `%s` | %s | %s |" % (m, deg(r.value("noise_sweep", m, "rot_err_deg_mean", **{"noise.endpoint_px": noise})),
                                             mm(r.value("noise_sweep", m, "trans_err_m_mean", **{"noise.endpoint_px": noise}))))
    return "\n" + "\n".join(lines) + "\n"


def fig4_noise_free(r):
    parts = ["`%s` %s" % (m, deg(r.value("noise_sweep", m, "rot_err_deg_mean", **{"noise.endpoint_px": 0})))
             for m in r.methods("noise_sweep")]
    return ", ".join(parts)


def fig4_against_paper(r):
    noise = max(r.values("noise_sweep", "noise.endpoint_px"))
    rot = r.value("noise_sweep", DEFAULT, "rot_err_deg_mean", **{"noise.endpoint_px": noise})
    trans = r.value("noise_sweep", DEFAULT, "trans_err_m_mean", **{"noise.endpoint_px": noise})
    return "%.2g× in rotation and %.2g× in translation" % (PAPER_FIG4[0] / rot, PAPER_FIG4[1] / trans)


def fig4_wall_time(r):
    return "%s s" % sig(r.json("noise_sweep", "run.json")["experiment_time_s"], 2)


def table1(r):
    t = r.json("table1", "table1.json")
    cols = t["columns"]

    def us(seconds):
        return sig(seconds * 1e6) + " µs"

    def ms(seconds):
        return sig(seconds * 1e3) + " ms" if is_number(seconds) else (seconds or "–")

    def paper_order(name):  # the rows of the paper's Table 1, in its order
        for k, start in enumerate(("The proposed", "Yu", "Elqursh", "Taylor")):
            if name.startswith(start):
                return k
        return 4

    lines = ["| method | %s |" % " | ".join("minimum" if c == "minimum" else "%s lines" % c for c in cols),
             "|---|" + "---:|" * len(cols)]
    for name, m in t["methods"].items():
        cells = [us(s) + (" (%d line%s)" % (n, "" if n == 1 else "s") if c == "minimum" else "")
                 for c, n, s in zip(cols, m["lines"], m["seconds"])]
        lines.append("| `%s` | %s |" % (name, " | ".join(cells)))
    for name, seconds in sorted(t["paper"].items(), key=lambda item: paper_order(item[0])):
        lines.append("| paper: %s | %s |" % (name, " | ".join(ms(s) for s in seconds)))
    return "\n" + "\n".join(lines) + "\n"


def table1_ratios(r):
    t = r.json("table1", "table1.json")
    paper = t["paper"]["The proposed approach (trifocal-line EKF)"]
    ours = t["methods"][DEFAULT]["seconds"]
    i10, i30 = t["columns"].index("10"), t["columns"].index("30")
    return "about %d× faster than the paper's figures at 30 lines; the growth from 10 to 30 lines is ×%.2g here, ×%.2g there" % (
        round(paper[i30] / ours[i30], -2), ours[i30] / ours[i10], paper[i30] / paper[i10])


def table1_machine(r):
    t = r.json("table1", "table1.json")
    return "%s, %d cores, %s %s" % (t["machine"]["cpu"], t["machine"]["cores"], t["compiler"], t["build_type"])


def loop_path(r):
    return "%s m" % sig(r.value("loop", DEFAULT, "path_length_m_mean"))


def loop_table(r):
    trials = int(r.row("loop", DEFAULT)["trials"])
    has_max = "max_trans_err_m_mean" in r.row("loop", DEFAULT)
    head = "| method (mean of %d trials) | start–end gap | gap / path | ATE (RMSE) |%s new references |" % (
        trials, " largest error |" if has_max else "")
    lines = [head, "|---|---:|---:|---:|" + ("---:|" if has_max else "") + "---:|"]
    for m in r.methods("loop"):
        cells = [mm(r.value("loop", m, "end_gap_m_mean")), "%s %%" % sig(r.value("loop", m, "drift_pct_mean"), 2),
                 mm(r.value("loop", m, "ate_trans_m_mean"))]
        if has_max:
            cells.append(mm(r.value("loop", m, "max_trans_err_m_mean")))
        cells.append(sig(r.value("loop", m, "new_references_mean"), 2))
        lines.append("| `%s` | %s |" % (m, " | ".join(cells)))
    return "\n" + "\n".join(lines) + "\n"


def datasets_sentence(r):
    """The real excerpts: KITTI ATE per method, the EuRoC end gap of the line tracker."""
    def at(method, dataset, column):
        return r.value("datasets", method, column, dataset=dataset)
    kitti, euroc = "kitti_excerpt_1", "euroc_v1_01_excerpt"
    path = at("trifocal_line_ekf", kitti, "path_length_m_mean")
    others = ", ".join("`%s` %s m" % (m, sig(at(m, kitti, "ate_trans_m_mean"), 2))
                       for m in r.methods("datasets") if m != "trifocal_line_ekf")
    return ("On the KITTI excerpt (51 frames, %s m, ~1.2 m per frame) `trifocal_line_ekf` has an ATE of %s m, "
            "%s %% of the path (%s); on the EuRoC excerpt \"at rest\" its last pose is %s from its first "
            "after 95 frames" % (sig(path, 2), sig(at("trifocal_line_ekf", kitti, "ate_trans_m_mean"), 2),
                                 sig(100 * at("trifocal_line_ekf", kitti, "ate_trans_m_mean") / path, 2), others,
                                 mm(at("trifocal_line_ekf", euroc, "end_gap_m_mean"))))


# The scenes of results/frontend/detectors.md (measure_frontend) the README names, in its order.
DETECTOR_SCENES = (("room 752x480 (loop)", "room, 752 × 480"), ("corridor 640x480 (forward)", "corridor"),
                   ("paper scene 640x480 (paper motion)", "paper scene"))


def edlines_rows(r, table, column):
    """(path, [(row, label)]) of EDLines on each scene the README names, from a table of detectors.md."""
    path, rows = r.markdown_rows("frontend", "detectors.md", table=table)
    found = []
    for scene, label in DETECTOR_SCENES:
        row = [x for x in rows if x.get("scene") == scene and x.get("detector") == "edlines"]
        if not row or column not in row[0]:
            raise ResultsError("%s: no %s of edlines on '%s'" % (path, column, scene))
        found.append((row[0], label))
    return path, found


def detector_recall(r):
    """The front end's default detector (EDLines): recall of the visible ground-truth segments per rendered scene."""
    _, rows = edlines_rows(r, 0, "recall")
    found = ["%.1f %% (%s)" % (100 * float(row["recall"]), label) for row, label in rows]
    return "%s and %s" % (", ".join(found[:-1]), found[-1])


def detector_recall_draws(r):
    """The same recall pooled over the draws of detectors.md's draw table (measure_frontend --draws), with the
    worst draw's."""
    path, rows = edlines_rows(r, 1, "worst draw")
    found = ["%.1f %% (worst draw %.1f %%; %s)" % (100 * float(row["recall"]), 100 * float(row["worst draw"]), label)
             for row, label in rows]
    draws = {row["draws"] for row, _ in rows}
    if len(draws) != 1:
        raise ResultsError("%s: scenes over different numbers of draws" % path)
    return "over %s draws of each scene: %s and %s" % (draws.pop(), ", ".join(found[:-1]), found[-1])


# The rows of the draws table (measure_frontend --draws): (folder under results/, scene, label).
FRONTEND_DRAWS = (("frontend", "room 752x480 (loop)", "room loop, 752 × 480"),
                  ("frontend", "corridor 640x480 (forward)", "corridor walk, 640 × 480"),
                  ("frontend", "paper scene 640x480 (paper motion)", "paper scene"),
                  ("frontend/paper_scene_tracker", "paper scene 640x480 (paper motion)",
                   "paper scene, `paper_scene.json` of `frontend/tracker_configs/` and `frontend/frontend_configs/`"),
                  ("frontend/paper_scene_100_frames", "paper scene 640x480 (paper motion)",
                   "paper scene, the same options, 100 frames (the protocol's length)"),
                  ("frontend/paper_scene_100_frames_held_out", "paper scene 640x480 (paper motion)",
                   "paper scene, the same options, 100 frames, draws 301–400 (held out from the choice of options)"),
                  ("frontend", "room 640x480 (loop, default rig)", "room loop, default 640 × 480 rig"))


def frontend_draws_table(r):
    """trifocal_line_ekf from rendered images: ten draws of each scene (results/frontend/draws.md), a hundred
    of the paper scene with its options (results/frontend/paper_scene_tracker/draws.md), three hundred of
    it at the paper protocol's 100 frames (results/frontend/paper_scene_100_frames/draws.md) and a hundred
    more held out from the choice of its options (results/frontend/paper_scene_100_frames_held_out/)."""
    lines = ["| scene, options | draws | ATE from the images, median / max | images / the same tracker on "
             "the truth with the front end's noise (paper scene: the synthetic protocol), median / max | draws within 1.5× "
             "| stereo matches correct, worst draw | tracks correct, worst draw |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for folder, scene, label in FRONTEND_DRAWS:
        path, rows = r.markdown_rows(*folder.split("/"), "draws.md")
        row = [x for x in rows if x.get("scene") == scene]
        if not row or "ratio images / noisy median" not in row[0]:
            raise ResultsError("%s: no summary row of '%s'" % (path, scene))
        x = row[0]
        lines.append("| %s | %s | %s / %s mm | %s / %s | %s | %s %% | %s %% |" % (
            label, x["draws"], sig(float(x["ATE images median, mm"])), sig(float(x["max, mm"])),
            sig(float(x["ratio images / noisy median"]), 2), sig(float(x["max"]), 2), x["draws with ratio <= 1.5"],
            sig(100 * float(x["stereo matches correct, worst draw"])), sig(100 * float(x["tracks correct, worst draw"]))))
    return "\n" + "\n".join(lines) + "\n"


# (experiment, run title, method label -> name shown; None = every method but the ablation rows).
# The best setting measured (docs/long_sequences.md) follows each loop's default rows.
# The held-out seeds (long_room_heldout) check the settings chosen on the issue's.
BEST_SETTING = {"+ triangulation (gate) + endpoint residual":
                "refinement + consider + triangulation (gate) + endpoint residual",
                "refinement + consider, epipolar extent 3 px": "refinement + consider + epipolar extent 3 px"}
HELD_OUT = dict(BEST_SETTING, **{"refinement + consider": "refinement + consider"})
# The process noise lowered toward the loop's motion with a fixed endpoint sigma
# (long_room_process_noise): chosen on seeds 1 and 2, checked on seeds 3 (long_room_fresh_seeds)
# and on the slow loop (long_slow_loop_process_noise).
# The process noise adapted online between the default and a floor of 5e-5 (filter.adaptive_process_noise):
# the same setting on every long run.
# And with the refinement's keyframes dense over a reference pair's life (every 5th frame and
# 5 mm, 300 kept; the solve then eliminates the poses): the same row in the six configs.
ADAPTIVE_Q = {"extent 3 px, adaptive Q, fixed R 1 px":
              "refinement + consider + epipolar extent 3 px + adaptive process noise, fixed R 1 px",
              "extent 3 px, adaptive Q, fixed R 1 px, keyframes 5 frames and 5 mm apart, 300 kept":
              "refinement + consider + epipolar extent 3 px + adaptive process noise, fixed R 1 px + dense keyframes (5 frames, 5 mm, 300 kept)"}
PROCESS_NOISE = dict(ADAPTIVE_Q, **{"extent 3 px, accel 5e-5, fixed R 1 px":
                                    "refinement + consider + epipolar extent 3 px + process noise 5e-5, fixed R 1 px"})
# The corridor walk sways: it keeps the default process noise, with the fixed endpoint sigma.
FIXED_R = dict(ADAPTIVE_Q, **{"extent 3 px, fixed R 1 px": "refinement + consider + epipolar extent 3 px, fixed R 1 px"})
FRESH = dict(PROCESS_NOISE, **{k: BEST_SETTING[k] for k in ("refinement + consider, epipolar extent 3 px",)})
# The preset long_run_consistent (issue 16, the covariance): one row in each *_placement config;
# at +-0.25 px with R at that noise, with and without its robust start's determined directions.
PLACEMENT = {"long_run_consistent": "preset long_run_consistent"}
LOW_NOISE = {"long_run_consistent, R at 0.144 px, RANSAC on every direction":
             "preset long_run_consistent, R at 0.144 px, RANSAC on every direction",
             "long_run_consistent, R at 0.144 px": "preset long_run_consistent, R at 0.144 px"}
LONG_RUNS = (("long_room", "room loop, 1428 frames", None),
             ("long_room_endpoint_residual", "room loop, 1428 frames", BEST_SETTING),
             ("long_room_process_noise", "room loop, 1428 frames", PROCESS_NOISE),
             ("long_room_heldout", "room loop, 1428 frames, held-out seeds", HELD_OUT),
             ("long_room_process_noise_heldout", "room loop, 1428 frames, held-out seeds", PROCESS_NOISE),
             ("long_room_placement", "room loop, 1428 frames", PLACEMENT),
             ("long_room_fresh_seeds", "room loop, 1428 frames, fresh seeds", FRESH),
             ("long_room_placement_heldout", "room loop, 1428 frames, held-out seeds", PLACEMENT),
             ("long_room_placement_fresh", "room loop, 1428 frames, fresh seeds", PLACEMENT),
             ("long_slow_loop", "room loop, 10000 frames", None),
             ("long_slow_loop_endpoint_residual", "room loop, 10000 frames", BEST_SETTING),
             ("long_slow_loop_process_noise", "room loop, 10000 frames", PROCESS_NOISE),
             ("long_slow_loop_placement", "room loop, 10000 frames", PLACEMENT),
             ("long_slow_loop_point_tracker", "room loop, 10000 frames", None),
             ("long_corridor", "corridor walk, 301 frames", None),
             ("long_corridor_process_noise", "corridor walk, 301 frames", FIXED_R),
             ("long_corridor_placement", "corridor walk, 301 frames", PLACEMENT),
             ("long_corridor_placement_low_noise", "corridor walk, 301 frames, ±0.25 px", LOW_NOISE),
             ("long_corridor_slow", "corridor walk, 1201 frames", None),
             ("long_corridor_slow_process_noise", "corridor walk, 1201 frames", FIXED_R),
             ("long_corridor_slow_placement", "corridor walk, 1201 frames", PLACEMENT))


def endpoint_model(r, experiment, row):
    """The row's endpoint model: its sweep value, else the experiment's simulation's."""
    if row.get("noise.endpoints"):
        return row["noise.endpoints"]
    return r.json(experiment, "config.resolved.json")["simulation"]["noise"]["endpoints"]


def long_runs_table(r):
    """ATE and largest error in % of the path, NEES, beyond 3 sigma: every method of the long-run configs."""
    lines = ["| run | endpoints | method | ATE | largest error | NEES (6 dof) | beyond 3σ |",
             "|---|---|---|---:|---:|---:|---:|"]
    for experiment, title, shown in LONG_RUNS:
        for row in r.summary(experiment):
            if shown is None and row["method"].startswith("refinement "):
                continue  # the ablation rows of long_room: docs/long_sequences.md
            if shown is not None and row["method"] not in shown:
                continue
            method = row["method"] if shown is None else shown[row["method"]]
            path = float(row["path_length_m_mean"])
            ate, largest = float(row["ate_trans_m_mean"]), float(row["max_trans_err_m_mean"])
            lines.append("| %s (%d trials) | %s | `%s` | %s (%s %%) | %s (%s %%) | %s | %s %% |" % (
                title, int(row["trials"]), endpoint_model(r, experiment, row), method, mm(ate), sig(100 * ate / path, 2),
                mm(largest), sig(100 * largest / path, 2), sig(float(row["nees_mean"]), 2),
                sig(float(row["beyond_3sigma_pct_mean"]), 2)))
    return "\n" + "\n".join(lines) + "\n"


FEATURE_LINES = (2, 4, 10, 20, 40)


def feature_count_table(r):
    lines_axis = [n for n in FEATURE_LINES if n in r.values("feature_count", "max_features")]
    rates = r.values("feature_count", "outliers.rate")
    lines = ["| method | outliers | %s |" % " | ".join("%d lines" % n for n in lines_axis),
             "|---|---:|" + "---:|" * len(lines_axis)]
    for m in r.methods("feature_count"):
        for rate in rates:
            cells = []
            for n in lines_axis:
                at = {"max_features": n, "outliers.rate": rate}
                cells.append("%s / %s" % (deg(r.value("feature_count", m, "rot_err_deg_mean", **at)),
                                          sig(r.value("feature_count", m, "rot_err_deg_median", **at))))
            lines.append("| `%s` | %s %% | %s |" % (m, sig(100 * rate), " | ".join(cells)))
    return "\n" + "\n".join(lines) + "\n"


def faithful_fixed_r(r):
    methods = r.methods("faithful_fixed_r")
    measured, guessed = methods[0], methods[1]
    trials = int(r.row("faithful_fixed_r", measured)["trials"])
    return "%s (median %s, %s) over %d trials; the earlier guessed R gave %s" % (
        deg(r.value("faithful_fixed_r", measured, "rot_err_deg_mean")),
        deg(r.value("faithful_fixed_r", measured, "rot_err_deg_median")),
        mm(r.value("faithful_fixed_r", measured, "trans_err_m_mean")), trials,
        deg(r.value("faithful_fixed_r", guessed, "rot_err_deg_mean")))


def endpoints_comparison(endpoints):
    def make(r):
        at = {"noise.endpoints": endpoints}
        return "%s against %s" % (deg(r.value("error_vs_frame", POINTS, "rot_err_deg_mean", **at)),
                                  deg(r.value("error_vs_frame", DEFAULT, "rot_err_deg_mean", **at)))
    return make


def sliding_comparison(r):
    at = {"noise.endpoints": "sliding"}
    return "%s against %s" % (deg(r.value("error_vs_frame", DEFAULT, "rot_err_deg_mean", **at)),
                              deg(r.value("error_vs_frame", POINTS, "rot_err_deg_mean", **at)))


def focal_200(r):
    focal = max(r.values("focal_sweep", "focal_error_px"))
    methods = r.methods("focal_sweep")
    rot = {m: r.value("focal_sweep", m, "rot_err_deg_mean", focal_error_px=focal) for m in methods}
    trans = {m: r.value("focal_sweep", m, "trans_err_m_mean", focal_error_px=focal) for m in methods}
    # The methods that agree (within 50 % of the median rotation error) give the band; any other
    # is named with its own numbers, so that a method far off cannot hide in a wide band.
    median = sorted(rot.values())[len(rot) // 2]
    agree = [m for m in methods if abs(rot[m] - median) <= 0.5 * median]
    others = [m for m in methods if m not in agree]
    rots = [rot[m] for m in agree]
    trans_agree = [trans[m] for m in agree]
    text = "%s–%s and %s–%s mm at frame 100 (`results/focal_sweep/`), against the paper's < %s and < %s; %s agree to within %d %%" % (
        sig(min(rots)), deg(max(rots)), sig(1000 * min(trans_agree)), sig(1000 * max(trans_agree)), deg(PAPER_FIG5[0]),
        mm(PAPER_FIG5[1]), "all %d methods" % len(agree) if not others else "these %d methods" % len(agree),
        round(100.0 * max(max(rots) / min(rots), max(trans_agree) / min(trans_agree)) - 100.0))
    if others:
        text += " (outside this band: %s)" % ", ".join("`%s` %s / %s mm" % (m, deg(rot[m]), sig(1000 * trans[m])) for m in others)
    return text


def taylor_fig6(r):
    """Taylor & Kriegman at frame 100 of Fig. 6 (5 and 20 frames), placed against the EKFs."""
    def at(method, endpoints):
        rot = r.value("error_vs_frame", method, "rot_err_deg_mean", **{"noise.endpoints": endpoints})
        trans = r.value("error_vs_frame", method, "trans_err_m_mean", **{"noise.endpoints": endpoints})
        return rot, trans

    def pair(v):
        return "%s / %s" % (deg(v[0]), mm(v[1]))

    def side(v, other):
        if v[0] > other[0] and v[1] > other[1]:
            return "above"
        if v[0] < other[0] and v[1] < other[1]:
            return "below"
        return "between in rotation and translation"

    k5, k20 = "taylor_line_sfm", "taylor_line_sfm (K = 20)"
    improved, faithful = at(DEFAULT, "fixed"), at(FAITHFUL, "fixed")
    return ("it reaches %s at frame 100 with 5 frames and %s with 20 (sliding endpoints: %s and %s): "
            "%s the improved trifocal EKF (%s), %s the faithful one (%s)" % (
                pair(at(k5, "fixed")), pair(at(k20, "fixed")), pair(at(k5, "sliding")), pair(at(k20, "sliding")),
                side(at(k5, "fixed"), improved), pair(improved), side(at(k5, "fixed"), faithful), pair(faithful)))


GENERATORS = {
    "fig4_table": fig4_table,
    "fig4_noise_free": fig4_noise_free,
    "fig4_against_paper": fig4_against_paper,
    "fig4_wall_time": fig4_wall_time,
    "table1": table1,
    "table1_ratios": table1_ratios,
    "table1_machine": table1_machine,
    "loop_path": loop_path,
    "loop_table": loop_table,
    "long_runs_table": long_runs_table,
    "datasets_sentence": datasets_sentence,
    "detector_recall": detector_recall,
    "detector_recall_draws": detector_recall_draws,
    "frontend_draws_table": frontend_draws_table,
    "feature_count_table": feature_count_table,
    "faithful_fixed_r": faithful_fixed_r,
    "fixed_endpoints": endpoints_comparison("fixed"),
    "sliding_endpoints": sliding_comparison,
    "focal_200": focal_200,
    "taylor_fig6": taylor_fig6,
}


def fill(text, results):
    """The README with every generated block refilled; raises ResultsError on an unknown block."""
    def replace(match):
        name = match.group(2)
        if name not in GENERATORS:
            raise ResultsError("README block 'generated:%s' has no generator (known: %s)" % (name, ", ".join(sorted(GENERATORS))))
        return match.group(1) + GENERATORS[name](results) + match.group(4)

    return BLOCK.sub(replace, text)


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 when README.md is out of date")
    parser.add_argument("--readme", default=os.path.join(here, "README.md"))
    parser.add_argument("--results", default=os.path.join(here, "results"))
    args = parser.parse_args()
    try:
        with open(args.readme, encoding="utf-8") as f:
            current = f.read()
        if not BLOCK.search(current):
            raise ResultsError("%s: no generated block" % args.readme)
        wanted = fill(current, Results(args.results))
    except (ResultsError, OSError, KeyError, ValueError) as e:
        sys.stderr.write("update_readme.py: error: %s\n" % e)
        return 1
    if args.check:
        if wanted == current:
            print("update_readme.py: %s agrees with %s" % (args.readme, args.results))
            return 0
        sys.stdout.writelines(difflib.unified_diff(current.splitlines(True), wanted.splitlines(True),
                                                   args.readme, "from " + args.results))
        sys.stderr.write("update_readme.py: error: %s does not match %s; run scripts/update_readme.py\n"
                         % (args.readme, args.results))
        return 1
    if wanted != current:
        tmp = "%s.tmp.%d" % (args.readme, os.getpid())
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(wanted)
        os.replace(tmp, args.readme)
        print("update_readme.py: updated %s" % args.readme)
    else:
        print("update_readme.py: %s is up to date" % args.readme)
    return 0


if __name__ == "__main__":
    sys.exit(main())
