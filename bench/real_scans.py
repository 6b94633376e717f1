#!/usr/bin/python3
"""The cloud repairs on real sensor scans (../shared/data/real): holes punched where the truth is known,
whole scans, denoising roughness, an airborne LiDAR tile. Every definition is implemented here.

  1 holes      each Kinect scan x seed: 8 discs of 6-20 px punched in image space, each on one surface (the
               disc and a 2-px ring valid, their depth spread < 3 % of the median, discs with rings not
               touching; numpy default_rng(seed)); `fill-holes` against a harmonic image-space fill, scored.
  2 whole      `fill-holes` and `denoise` on each whole Kinect scan: seconds, added points, free-space
               violations, width x height kept.
  3 roughness  RMS residual of 5 cm neighbourhoods of the largest plane (RANSAC on the input, 1.5 cm,
               500 seeded tries; 4000 seeded points) to their own planes: input, `denoise`, PCL's MLS.
  4 lidar      terrain_csite3 x seed: 8 vertical cylinders of --radius-m punched through; `fill-holes`
               (seconds, peak RSS) against a rasterised harmonic grid fill, scored.

Scores (distances in the cloud's units, then divided by the local spacing s, the median distance to the
input's nearest points at that place, computed as the harness does: the 5 nearest input points, the
nearest dropped):
  added            output points farther than 1e-6 x the input's extent from every input point
  coverage         share of the removed real points within 1.5 s of an added point
  removed_to_out   mean distance of the removed points to the nearest added point, / s (each capped at 1000)
  in holes         added points projecting within 1.5 px of a punched disc (organised) or within 2 s of a
                   cylinder (LiDAR, in xy); "outside" = the rest
  free space       added points projecting onto a pixel whose 3 x 3 neighbourhood's nearest measured depth is
                   more than max(3 s, 1 % of that depth) behind them: space the sensor saw through

usage: bench/real_scans.py [--quick] [--seeds 1,2,3] [--radius-m 8,25] [--shared ../shared/data]
                           [--tool build/pcl_patchdict] [--out bench/results/real_scans] [--work DIR]
--quick: mosd_learn0 with seed 1, the LiDAR tile with seed 1, no MLS at 3 cm (30-50 s on 2 cores).
Writes OUT/real_scans.md (tables, commands, commit), OUT/{holes,whole,roughness,lidar}.csv and
OUT/real_scans.log (each command and its stderr). Only numpy and scipy; binary_compressed PCDs are first
converted with `pcl_convert_pcd_ascii_binary IN OUT 1` (pcl-tools), as is `pcl_mls_smoothing`.
"""
import argparse
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from real_scans_common import (read_pcd, write_pcd, xyz, finite_rows, fit_camera, split_added,  # noqa: E402
                                free_space_violations, score, punch_image, punch_cylinders, image_fill,
                                grid_fill, largest_plane, roughness_mm)
from reproduce import git_commit  # noqa: E402  (the same "commit (with uncommitted changes)" line)

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
ORGANISED = ["mosd_learn0", "mosd_learn20", "mosd_learn28", "mosd_learn40", "kinect_frame_142256"]
LIDAR = "terrain_csite3"
MLS_RADII = [0.01, 0.02, 0.03]
class Runner:
    def __init__(self, log):
        self.log = log

    def __call__(self, command, env=None):
        """Runs a command; -> (wall seconds, peak RSS of the child in MB, stdout)."""
        command = [str(c) for c in command]
        with open(self.log, "a") as log, tempfile.TemporaryFile() as stdout:
            log.write("$ " + " ".join(command) + "\n")
            log.flush()
            # /usr/bin/time measures the peak RSS: a child forked from this process would count the pages it
            # shares with it until its exec
            peak_file = tempfile.NamedTemporaryFile(suffix=".txt", delete=False).name
            start = time.monotonic()
            child = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", peak_file, *command], stdout=stdout,
                                   stderr=log, env=env)
            seconds = time.monotonic() - start
            stdout.seek(0)
            text = stdout.read().decode()
            with open(peak_file) as f:
                peak = f.read().split()
            os.unlink(peak_file)
        if child.returncode != 0:
            sys.exit("real_scans.py: failed (exit %d): %s — see %s" % (child.returncode, " ".join(command), self.log))
        return seconds, float(peak[-1]) / 1024.0 if peak else float("nan"), text


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def fmt(v, digits=3):
    return "%.*f" % (digits, v) if isinstance(v, float) else str(v)


def holes_step(a, run, work, scans, seeds):
    rows = []
    for name in scans:
        arr, info = read_pcd(a.real / (name + ".pcd"), work)
        W, H = info["width"], info["height"]
        cam = fit_camera(xyz(arr), W, H)  # the scorer's camera: from the whole scan
        for seed in seeds:
            case = work / ("%s_seed%d" % (name, seed))
            case.mkdir(exist_ok=True)
            holed, removed, holes = punch_image(arr, W, H, seed)
            write_pcd(case / "holed.pcd", holed, W, H, info["viewpoint"])
            seconds, _, text = run([a.tool, "fill-holes", case / "holed.pcd", "-o", case / "out.pcd", "--json"])
            start = time.monotonic()
            reference = image_fill(holed, W, H)
            ref_seconds = time.monotonic() - start
            write_pcd(case / "image_fill.pcd", reference, W, H, info["viewpoint"])
            P_in = xyz(holed)

            def in_holes(added):
                col = cam["fx"] * added[:, 0] / added[:, 2] + cam["cx"]
                row = cam["fy"] * added[:, 1] / added[:, 2] + cam["cy"]
                return np.any([(row - cy) ** 2 + (col - cx) ** 2 <= (r + 1.5) ** 2 for cy, cx, r in holes], axis=0)

            ours = score(P_in, W, H, removed, xyz(read_pcd(case / "out.pcd", work)[0]), in_holes, cam)
            ref = score(P_in, W, H, removed, xyz(reference), in_holes, cam)
            row = {"scan": name, "seed": seed, "removed": len(removed), "seconds": round(seconds, 3),
                   "image_fill_seconds": round(ref_seconds, 3)}
            for key in ("coverage", "removed_to_out", "added", "added_in_holes", "added_outside_holes",
                        "free_space_violations", "input_points_lost", "input_points_moved_over_3s"):
                row[key], row["image_fill_" + key] = ours[key], ref[key]
            rows.append(row)
            print("holes  %-20s seed %d: coverage %.3f / %.3f, removed->out %.3f / %.3f s, added %d / %d "
                  "(outside %d / %d), free space %d / %d, %.2f s" % (
                      name, seed, row["coverage"], row["image_fill_coverage"], row["removed_to_out"],
                      row["image_fill_removed_to_out"], row["added"], row["image_fill_added"],
                      row["added_outside_holes"], row["image_fill_added_outside_holes"],
                      row["free_space_violations"], row["image_fill_free_space_violations"], seconds), flush=True)
            if not a.keep:
                shutil.rmtree(case)
    write_csv(a.out / "holes.csv", rows)
    md = ["| scan | seed | removed | coverage ours / image fill | removed→out (s) ours / image fill | added ours / "
          "image fill | added outside the holes | free-space violations | seconds ours / image fill |",
          "|---|---:|---:|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %d | %d | %.3f / %.3f | %.3f / %.3f | %d / %d | %d / %d | %d / %d | %.2f / %.2f |" % (
            r["scan"], r["seed"], r["removed"], r["coverage"], r["image_fill_coverage"], r["removed_to_out"],
            r["image_fill_removed_to_out"], r["added"], r["image_fill_added"], r["added_outside_holes"],
            r["image_fill_added_outside_holes"], r["free_space_violations"], r["image_fill_free_space_violations"],
            r["seconds"], r["image_fill_seconds"]))
    return md


def whole_step(a, run, work, scans):
    rows, denoised = [], {}
    for name in scans:
        src = work / (name + ".pcd")
        arr, info = read_pcd(a.real / (name + ".pcd"), work)
        W, H = info["width"], info["height"]
        write_pcd(src, arr, W, H, info["viewpoint"])  # binary: what the tools are given
        P_in = xyz(arr)
        cam = fit_camera(P_in, W, H)
        row = {"scan": name, "points": int(finite_rows(P_in).sum())}
        for command in ("fill-holes", "denoise"):
            out = work / ("%s_%s.pcd" % (name, command))
            seconds, peak, _ = run([a.tool, command, src, "-o", out, "--json"])
            out_arr, out_info = read_pcd(out, work)
            fin, tree, _, added = split_added(P_in, xyz(out_arr))
            key = command.replace("-", "_")
            row.update({key + "_seconds": round(seconds, 3), key + "_peak_mb": round(peak, 1),
                        key + "_not_input_points": len(added),
                        key + "_free_space_violations": free_space_violations(P_in, W, H, added, cam, tree),
                        key + "_kept_grid": int((out_info["width"], out_info["height"]) == (W, H)),
                        key + "_width_x_height": "%d×%d" % (out_info["width"], out_info["height"])})
            if command == "denoise":
                denoised[name] = (out, seconds)
        row["image_fill_added"] = len(split_added(P_in, xyz(image_fill(arr, W, H)))[3])
        rows.append(row)
        print("whole  %-20s fill-holes %.2f s, %d added (image fill %d), %d free-space; denoise %.1f s, %d moved "
              "or new, %d free-space; %s / %s" % (
                  name, row["fill_holes_seconds"], row["fill_holes_not_input_points"], row["image_fill_added"],
                  row["fill_holes_free_space_violations"], row["denoise_seconds"], row["denoise_not_input_points"],
                  row["denoise_free_space_violations"], row["fill_holes_width_x_height"],
                  row["denoise_width_x_height"]), flush=True)
    write_csv(a.out / "whole.csv", rows)
    md = ["| scan | points | `fill-holes` s | added (image fill) | free-space violations | W×H out | `denoise` s | "
          "points moved or new | free-space violations | W×H out |", "|---|---:|---:|---:|---:|---|---:|---:|---:|---|"]
    for r in rows:
        md.append("| %s | %d | %.2f | %d (%d) | %d | %s | %.1f | %d | %d | %s |" % (
            r["scan"], r["points"], r["fill_holes_seconds"], r["fill_holes_not_input_points"], r["image_fill_added"],
            r["fill_holes_free_space_violations"], r["fill_holes_width_x_height"], r["denoise_seconds"],
            r["denoise_not_input_points"], r["denoise_free_space_violations"], r["denoise_width_x_height"]))
    return md, denoised


def roughness_step(a, run, work, scans, denoised, radii):
    rows = []
    env = dict(os.environ, OMP_NUM_THREADS="2")
    for name in scans:
        src = work / (name + ".pcd")
        P0 = xyz(read_pcd(src, work)[0])
        P0 = P0[finite_rows(P0)]
        plane = largest_plane(P0)
        base, region = roughness_mm(P0, plane)
        row = {"scan": name, "plane_points": region, "input_mm": round(base, 4)}
        out, seconds = denoised[name]
        clouds = [("denoise", out, seconds)]
        for radius in radii:
            mls = work / ("%s_mls%g.pcd" % (name, radius))
            seconds, _, _ = run(["pcl_mls_smoothing", src, mls, "-radius", radius], env=env)
            clouds.append(("mls_%gcm" % (100 * radius), mls, seconds))
        for key, path, seconds in clouds:
            P = xyz(read_pcd(path, work)[0])
            mm = roughness_mm(P[finite_rows(P)], plane)[0]
            row.update({key + "_mm": round(mm, 4), key + "_below_input_pct": round(100 * (1 - mm / base), 1),
                        key + "_seconds": round(seconds, 2)})
        rows.append(row)
        print("rough  %-20s " % name + ", ".join("%s %.3f mm" % (k[:-3], v) for k, v in row.items()
                                                   if k.endswith("_mm")), flush=True)
    write_csv(a.out / "roughness.csv", rows)
    keys = ["denoise"] + ["mls_%gcm" % (100 * r) for r in radii]
    md = ["| scan | plane points | input mm | " + " | ".join(
        "`denoise`" if k == "denoise" else "MLS %s cm" % k[4:-2] for k in keys) + " |",
        "|---|---:|---:|" + "---:|" * len(keys)]
    for r in rows:
        md.append("| %s | %d | %.3f | " % (r["scan"], r["plane_points"], r["input_mm"]) + " | ".join(
            "%.3f (−%.1f %%, %.1f s)" % (r[k + "_mm"], r[k + "_below_input_pct"], r[k + "_seconds"]) for k in keys)
            + " |")
    return md


def lidar_step(a, run, work, seeds, rmin, rmax):
    rows = []
    arr, info = read_pcd(a.real / (LIDAR + ".pcd"), work)
    for seed in seeds:
        case = work / ("%s_seed%d" % (LIDAR, seed))
        case.mkdir(exist_ok=True)
        holed, removed, holes, s = punch_cylinders(arr, seed, rmin, rmax)
        write_pcd(case / "holed.pcd", holed, len(holed), 1, info["viewpoint"])
        seconds, peak, _ = run([a.tool, "fill-holes", case / "holed.pcd", "-o", case / "out.pcd", "--json"])
        start = time.monotonic()
        reference = grid_fill(holed)
        ref_seconds = time.monotonic() - start
        write_pcd(case / "grid_fill.pcd", reference, len(reference), 1, info["viewpoint"])
        P_in = xyz(holed)

        def in_holes(added):
            return np.any([np.hypot(added[:, 0] - hx, added[:, 1] - hy) <= hr + 2 * s for hx, hy, hr in holes],
                          axis=0)

        ours = score(P_in, len(holed), 1, removed, xyz(read_pcd(case / "out.pcd", work)[0]), in_holes)
        ref = score(P_in, len(holed), 1, removed, xyz(reference), in_holes)
        row = {"seed": seed, "radius_m": "%g-%g" % (rmin, rmax), "removed": len(removed),
               "seconds": round(seconds, 3), "peak_mb": round(peak, 1), "grid_fill_seconds": round(ref_seconds, 3)}
        for key in ("coverage", "removed_to_out", "added", "added_in_holes", "added_outside_holes",
                    "input_points_lost", "input_points_moved_over_3s"):
            row[key], row["grid_fill_" + key] = ours[key], ref[key]
        rows.append(row)
        print("lidar  seed %d: coverage %.3f / %.3f, removed->out %.3f / %.3f s, added %d (%d in holes) / %d (%d), "
              "%.2f s, %.0f MB" % (seed, row["coverage"], row["grid_fill_coverage"], row["removed_to_out"],
                                   row["grid_fill_removed_to_out"], row["added"], row["added_in_holes"],
                                   row["grid_fill_added"], row["grid_fill_added_in_holes"], seconds, peak), flush=True)
        if not a.keep:
            shutil.rmtree(case)
    write_csv(a.out / "lidar.csv", rows)
    md = ["| seed | removed | coverage ours / grid | removed→out (s) ours / grid | added (in holes) ours | "
          "added (in holes) grid | seconds ours / grid | peak RSS ours |", "|---:|---:|---|---|---:|---:|---|---:|"]
    for r in rows:
        md.append("| %d | %d | %.3f / %.3f | %.3f / %.3f | %d (%d) | %d (%d) | %.2f / %.2f | %.0f MB |" % (
            r["seed"], r["removed"], r["coverage"], r["grid_fill_coverage"], r["removed_to_out"],
            r["grid_fill_removed_to_out"], r["added"], r["added_in_holes"], r["grid_fill_added"],
            r["grid_fill_added_in_holes"], r["seconds"], r["grid_fill_seconds"], r["peak_mb"]))
    return md


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--seeds", default="1,2,3")
    parser.add_argument("--radius-m", default="8,25", help="LiDAR cylinder radii, min,max (cloud units)")
    parser.add_argument("--shared", default=str(ROOT.parent / "shared" / "data"))
    parser.add_argument("--tool", default=str(ROOT / "build" / "pcl_patchdict"))
    parser.add_argument("--out", default=str(HERE / "results" / "real_scans"))
    parser.add_argument("--work", help="keep the intermediate clouds here (default: a temporary folder)")
    a = parser.parse_args()
    a.real, a.tool, a.out = Path(a.shared).resolve() / "real", Path(a.tool).resolve(), Path(a.out).resolve()
    if not a.real.is_dir():
        sys.exit("real_scans.py: %s not found — the scans live in ../shared/data/real" % a.real)
    if not a.tool.exists():
        sys.exit("real_scans.py: %s not built — run scripts/build.sh first" % a.tool)
    for program in ("pcl_convert_pcd_ascii_binary", "pcl_mls_smoothing", "/usr/bin/time"):
        if shutil.which(program) is None:
            sys.exit("real_scans.py: %s not found (Debian's pcl-tools)" % program)
    a.out.mkdir(parents=True, exist_ok=True)
    a.keep = a.work is not None
    work = Path(a.work).resolve() if a.keep else Path(tempfile.mkdtemp(prefix="real_scans_"))
    work.mkdir(parents=True, exist_ok=True)
    seeds = [int(s) for s in a.seeds.split(",") if s]
    scans, radii = ORGANISED, MLS_RADII
    if a.quick:
        seeds, scans, radii = seeds[:1], ORGANISED[:1], MLS_RADII[:2]
    rmin, rmax = (float(v) for v in a.radius_m.split(","))
    log = a.out / "real_scans.log"
    log.write_text("# real_scans.py %s\n" % " ".join(sys.argv[1:]))
    run = Runner(log)
    commit = git_commit()
    start = time.monotonic()
    try:
        steps = []
        t = time.monotonic()
        holes_md = holes_step(a, run, work, scans, seeds)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        whole_md, denoised = whole_step(a, run, work, scans)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        rough_md = roughness_step(a, run, work, scans, denoised, radii)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        lidar_md = lidar_step(a, run, work, seeds, rmin, rmax)
        steps.append(time.monotonic() - t)
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    seconds = time.monotonic() - start
    tool = "pcl_patchdict"
    md = ["# Real sensor scans", "",
          "*`bench/real_scans.py%s`, commit %s, %s UTC, %.0f s (steps %s s); `%s` built %s UTC; scans from "
          "`%s`.*" % (" --quick" if a.quick else "", commit, time.strftime("%Y-%m-%d %H:%M", time.gmtime()), seconds,
                      " / ".join("%.0f" % s for s in steps), a.tool.name,
                      time.strftime("%Y-%m-%d %H:%M", time.gmtime(a.tool.stat().st_mtime)), a.real),
          "",
          "s is the local spacing (median distance to the nearby input points). Added: output points that are not "
          "input points (to 1e-6 of the extent). Free-space violation: an added point in front of the nearest "
          "measured depth of its pixel's 3×3 neighbourhood by more than max(3 s, 1 % of that depth). Seconds are "
          "wall time of the whole command (load, work, write) on a shared 2-core machine.", "",
          "### 1. Punched holes, organised Kinect scans", "",
          "8 discs of 6–20 px per case, each on one surface (disc and 2-px ring valid, depth spread < 3 %%), "
          "`numpy.random.default_rng(seed)`; the removed real points are the truth. "
          "Commands: `%s fill-holes holed.pcd -o out.pcd --json`; the reference is this script's harmonic "
          "image-space fill (Laplace in depth over each enclosed NaN region of ≤ 2000 px with rim spread < 3 %%; "
          "x, y on the fitted pinhole camera's rays; timed in-process). Coverage: share of removed points "
          "within 1.5 s of an added point; removed→out: their mean distance to the nearest added point / s; "
          "outside the holes: added points projecting farther than 1.5 px from every disc." % tool, ""] + holes_md + [
          "", "### 2. Whole organised scans", "",
          "Commands: `%s fill-holes SCAN.pcd -o OUT.pcd --json` and `%s denoise SCAN.pcd -o OUT.pcd --json` "
          "(SCAN converted to binary). For `denoise`, every point it moves along its ray counts as not an input "
          "point, so its free-space column checks the moved points. W×H out: the output header's grid; "
          "(image fill): what the reference fill adds to the whole scan." % (tool, tool), ""] + whole_md + [
          "", "### 3. Denoising roughness on the largest plane", "",
          "The plane: RANSAC on the input (500 tries, `default_rng(0)`, points within 1.5 cm). For each cloud, "
          "its points within 1.5 cm of that plane; 4000 of them (`default_rng(1)`) each get a plane fitted to "
          "their 5 cm neighbourhood (≥ 10 points); the RMS of all those residuals, in mm (−x %%: below the "
          "input's). Commands: `%s denoise SCAN.pcd -o OUT.pcd` (the run of step 2) and "
          "`OMP_NUM_THREADS=2 pcl_mls_smoothing SCAN.pcd MLS.pcd -radius R` (PCL's defaults: order 2)." % tool,
          ""] + rough_md + [
          "", "### 4. Airborne LiDAR tile (terrain_csite3, 377k points, unorganised)", "",
          "8 vertical cylinders of radius %g–%g m per seed punched through (each disc and a 3-s margin fully "
          "sampled, discs 6 s apart). Command: `%s fill-holes holed.pcd -o out.pcd --json` (peak RSS of the "
          "child, `/usr/bin/time -f %%M`). The reference is this script's rasterised harmonic grid fill (cells of 1.5 s, "
          "enclosed empty regions of ≤ 4000 cells, one point per cell; timed in-process). In holes: within "
          "radius + 2 s of a cylinder's axis." % (rmin, rmax, tool), ""] + lidar_md + [""]
    (a.out / "real_scans.md").write_text("\n".join(md))
    print("real_scans.py: wrote %s in %.0f s" % (a.out / "real_scans.md", seconds))


if __name__ == "__main__":
    main()
