#!/usr/bin/env python3
"""Every registered tracker on the simulator's real-motion sequences (docs/simulation.md,
"Motion profiles"): the street driven by the car profile (from a straight at speed, and starting
inside the turn), the room flown by the mav profile and the room carried by the handheld profile. Each sequence is rendered once (`simulate NAME --images`)
and tracked two ways with default options: `track` on its noise-free observations (seq.json) and
`track_images` on its pictures. Errors are `evaluate`'s, with alignment none (world = the first
left camera), as percentages of the ground-truth path.

    scripts/motion_profiles_table.py [--build DIR] [--work DIR] [--sequences A,B] OUT_DIR

Writes OUT_DIR/table.md (the table, with the machine and the commit) and OUT_DIR/table.csv (one
row per sequence, tracker and input), both or neither. WORK (default: a temporary folder, removed
afterwards) holds the rendered sequences and the trajectories.
"""
import argparse
import csv
import io
import json
import os
import platform
import subprocess
import sys
import tempfile
import time

SEQUENCES = ["street", "street_turn_start", "room_mav_752x480", "room_handheld_752x480"]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(command, **kwargs):
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if result.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(command), result.returncode, result.stderr.strip()))
    return result.stdout


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def lost_frames(log_path):
    """Frames whose status is `degraded` or `lost` in a --log CSV (track or track_images), and
    the frame count."""
    with open(log_path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return sum(1 for row in rows if row["status"] in ("degraded", "lost")), len(rows)


def path_length(tum_path):
    """Length of the polyline of a TUM trajectory's positions (m)."""
    points = []
    with open(tum_path) as f:
        for line in f:
            fields = line.split()
            if fields and not fields[0].startswith("#"):
                points.append(tuple(float(v) for v in fields[1:4]))
    return sum(sum((a - b) ** 2 for a, b in zip(p, q)) ** 0.5 for p, q in zip(points, points[1:]))


def evaluate(build, gt, est):
    metrics = json.loads(run([os.path.join(build, "bin", "evaluate"), "--gt", gt, "--est", est, "--format", "json"]))
    return metrics




def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="output folder (table.md, table.csv)")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--work", help="keep the rendered sequences and trajectories here")
    parser.add_argument("--sequences", default=",".join(SEQUENCES), help="named scenes, comma-separated")
    args = parser.parse_args()
    build = os.path.abspath(args.build)
    bin_dir = os.path.join(build, "bin")
    # Every registered tracker but the plumbing test (constant_pose), as run_experiment's "all".
    methods = [line.split("\t")[0] for line in run([os.path.join(bin_dir, "track"), "--list"]).splitlines()
               if "\t" in line and "plumbing test only" not in line]
    work_holder = None if args.work else tempfile.TemporaryDirectory(prefix="motion_profiles_")
    work = os.path.abspath(args.work or work_holder.name)
    os.makedirs(work, exist_ok=True)
    rows = []
    for name in args.sequences.split(","):
        folder = os.path.join(work, name)
        started = time.time()
        run([os.path.join(bin_dir, "simulate"), name, "--out", folder, "--images"], cwd=ROOT)
        print("%s: rendered in %.0f s" % (name, time.time() - started), file=sys.stderr)
        gt = os.path.join(folder, "gt.tum")
        length = path_length(gt)
        for method in methods:
            for source in ("observations", "images"):
                stem = os.path.join(folder, "%s_%s" % (method, source))
                started = time.time()
                if source == "observations":
                    run([os.path.join(bin_dir, "track"), "-m", method, "-i", os.path.join(folder, "seq.json"),
                         "-o", stem + ".tum", "--log", stem + ".csv"])
                else:
                    run([os.path.join(bin_dir, "track_images"), "--path", folder, "-m", method, "-o", stem + ".tum",
                         "--log", stem + ".csv"])
                seconds = time.time() - started
                metrics = evaluate(build, gt, stem + ".tum")
                not_tracking, frames = lost_frames(stem + ".csv")
                rows.append({"sequence": name, "method": method, "input": source,
                             "frames": frames, "path_length_m": length,
                             "ate_pct": 100.0 * metrics["ate_trans_m"]["rmse"] / length,
                             "max_error_pct": 100.0 * metrics["ate_trans_m"]["max"] / length,
                             "ate_rot_deg": metrics["ate_rot_deg"]["rmse"],
                             "not_tracking_frames": not_tracking, "seconds": seconds})
                print("%s %s %s: ATE %.2f %% of the path, largest %.2f %%, %d frames not tracking (%.0f s)"
                      % (name, method, source, rows[-1]["ate_pct"], rows[-1]["max_error_pct"], not_tracking, seconds),
                      file=sys.stderr)
    write_outputs(args.out, rows)
    if work_holder is not None:
        work_holder.cleanup()


def write_outputs(out, rows):
    commit = run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"]).strip()
    dirty = run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"]).strip() != ""
    table = io.StringIO()
    table.write("# Every tracker on the simulator's real-motion sequences\n\n")
    table.write("Generated by `scripts/motion_profiles_table.py` at commit %s%s on %s (%d cores). Each named "
                "sequence (`simulate NAME --images`, docs/simulation.md) tracked with default options: `track` on "
                "its noise-free observations and `track_images` on its rendered pictures. Errors against the ground "
                "truth with alignment none, as percentages of the path length; *not tracking*: frames whose status "
                "is `degraded` or `lost`.\n\n"
                % (commit, " (with uncommitted changes)" if dirty else "", cpu_model(), os.cpu_count()))
    table.write("| sequence | frames | path (m) | tracker | input | ATE (% of path) | largest error (% of path) "
                "| ATE rotation (deg) | not tracking | wall time (s) |\n")
    table.write("|---|---:|---:|---|---|---:|---:|---:|---:|---:|\n")
    for r in rows:
        table.write("| %s | %d | %.2f | %s | %s | %.2f | %.2f | %.2f | %d | %.0f |\n"
                    % (r["sequence"], r["frames"], r["path_length_m"], r["method"], r["input"], r["ate_pct"],
                       r["max_error_pct"], r["ate_rot_deg"], r["not_tracking_frames"], r["seconds"]))
    text_csv = io.StringIO()
    writer = csv.DictWriter(text_csv, fieldnames=list(rows[0].keys()), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    # Both files or neither: written beside their places, then renamed.
    os.makedirs(out, exist_ok=True)
    staged = []
    try:
        for file, text in (("table.md", table.getvalue()), ("table.csv", text_csv.getvalue())):
            path = os.path.join(out, file)
            with open(path + ".tmp", "w") as f:
                f.write(text)
            staged.append(path)
        for path in staged:
            os.replace(path + ".tmp", path)
    finally:
        for path in staged:
            if os.path.exists(path + ".tmp"):
                os.remove(path + ".tmp")


if __name__ == "__main__":
    try:
        main()
    except (RuntimeError, OSError) as e:
        print("motion_profiles_table: error: %s" % e, file=sys.stderr)
        sys.exit(1)
