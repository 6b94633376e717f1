#!/usr/bin/python3
"""The range-image repairs on spinning-LiDAR frames (Ouster, ../shared/data/real): holes punched where the
truth is known, whole frames, denoising roughness of the ground and a wall, frame rate. Every definition is
implemented here and in spinning_common.py (with real_scans_common.py's I/O and scores).

  1 holes      each frame x seed: 8 discs punched in the range image (radius 2-4 px on 32 beams, 3-8 px on
               128), each on one surface (the disc and a 2-px ring valid, their range spread < 3 % of the
               median, discs with rings not touching, off the first and last 2 beams; default_rng(seed));
               `fill-holes` against a harmonic range-image fill (range and direction), scored.
  2 whole      `fill-holes` and `denoise` on each whole frame: seconds, points not in the input, free-space
               violations, width x height kept.
  3 roughness  RMS residual of 0.5 m neighbourhoods of the ground (the largest plane, RANSAC on the input,
               0.1 m, 500 seeded tries) and of the largest wall (the largest plane among points > 0.5 m above
               the ground) to their own planes: input, `denoise`, PCL's MLS at several radii (with its
               free-space violations and the grid it writes).
  4 rate       `build/bench/frame_rate FRAME --frames 20 --threads T --json`, T = 1, 2: ms per frame.

Scores (s: the local spacing, the median distance to the 4 nearest input points, as the harness does):
  added            output points farther than 1e-6 x the input's extent from every input point
  coverage         share of the removed real points within 1.5 s of an added point
  removed_to_out   mean distance of the removed points to the nearest added point, / s (each capped at 1000)
  in holes         added points whose nearest measured beam direction (the input's, plus the removed pixels')
                   is within 1.5 angular steps and within radius + 1.5 px of a disc; "outside" = the rest
  free space       added points nearer the origin than the minimum measured range of the 3 x 3 beams around
                   their nearest beam by more than max(3 s, 1 % of that range); azimuth wraps, beams do not

usage: bench/spinning_scans.py [--quick] [--seeds 1,2,3] [--frames-dir ../shared/data/real]
                               [--tool build/pcl_patchdict] [--out build/spinning_scans] [--work DIR]
--quick: ouster_os1_32g with seed 1, MLS at 0.1 and 0.3 m, its rate only. Writes OUT/spinning_scans.md,
OUT/{holes,whole,roughness,rate}.csv and OUT/spinning_scans.log (each command and its stderr).
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from real_scans_common import read_pcd, write_pcd, xyz, finite_rows  # noqa: E402
from spinning_common import (punch_range_image, range_image_fill, score_holes, whole_frame_check,  # noqa: E402
                             ground_and_wall, plane_points, local_rms_mm, tilt_degrees, radius_px)
from reproduce import git_commit  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
FRAMES = ["ouster_os1_32g", "ouster_os2_32", "ouster_os1_128_f0", "ouster_os1_128_f1", "ouster_os1_128_f2"]
KINECT = "kinect_frame_142256"
MLS_RADII = [0.1, 0.2, 0.3, 0.5, 0.75, 1.0]
KEYS = ("coverage", "removed_to_out", "added", "added_in_holes", "added_outside_holes", "free_space_violations",
        "input_points_lost", "input_points_moved_over_3s")


def run(log, command, env=None):
    """Runs a command, its stderr to the log; exits non-zero when it fails. -> (wall seconds, stdout)."""
    command = [str(c) for c in command]
    with open(log, "a") as f:
        f.write("$ " + " ".join(command) + "\n")
        f.flush()
        start = time.monotonic()
        try:
            child = subprocess.run(command, stdout=subprocess.PIPE, stderr=f, env=env)
        except OSError as error:
            sys.exit("spinning_scans.py: cannot run %s: %s" % (command[0], error))
    if child.returncode != 0:
        sys.exit("spinning_scans.py: failed (exit %d): %s — see %s" % (child.returncode, " ".join(command), log))
    return time.monotonic() - start, child.stdout.decode()


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def load_frame(a, work, name):
    """-> (array, width, height, viewpoint, path of a binary copy in work)."""
    arr, info = read_pcd(a.frames_dir / (name + ".pcd"), work)
    src = work / (name + ".pcd")
    if not src.exists():
        write_pcd(src, arr, info["width"], info["height"], info["viewpoint"])
    return arr, info["width"], info["height"], info["viewpoint"], src


def hole_case(a, work, name, frame, seed):
    """One frame x seed: punch, run fill-holes and the baseline, score both. -> CSV row."""
    arr, W, H, viewpoint, _ = frame
    case = work / ("%s_seed%d" % (name, seed))
    case.mkdir(exist_ok=True)
    holed, removed, pixels, holes = punch_range_image(arr, W, H, seed)
    write_pcd(case / "holed.pcd", holed, W, H, viewpoint)
    np.save(case / "removed.npy", removed)
    np.save(case / "removed_pixels.npy", pixels)
    seconds, _ = run(a.log, [a.tool, "fill-holes", case / "holed.pcd", "-o", case / "out.pcd", "--json"])
    start = time.monotonic()
    reference = range_image_fill(holed, W, H)
    ref_seconds = time.monotonic() - start
    write_pcd(case / "range_image_fill.pcd", reference, W, H, viewpoint)
    out_arr, out_info = read_pcd(case / "out.pcd", work)
    ours = score_holes(holed, W, H, removed, pixels, holes, xyz(out_arr))
    ref = score_holes(holed, W, H, removed, pixels, holes, xyz(reference))
    row = {"frame": name, "seed": seed, "radius_px": "%d-%d" % radius_px(H), "removed": len(removed),
           "holes": " ".join("%d:%d:%d" % h for h in holes), "seconds": round(seconds, 3),
           "baseline_seconds": round(ref_seconds, 3),
           "kept_grid": int((out_info["width"], out_info["height"]) == (W, H))}
    for key in KEYS:
        row[key], row["baseline_" + key] = ours[key], ref[key]
    if not a.keep:
        shutil.rmtree(case)
    return row


def holes_step(a, work, frames, seeds):
    rows = []
    for name in frames:
        frame = load_frame(a, work, name)
        for seed in seeds:
            r = hole_case(a, work, name, frame, seed)
            rows.append(r)
            print("holes  %-18s seed %d: coverage %.4f / %.4f, removed->out %.3f / %.3f s, outside %d / %d, "
                  "free space %d / %d, grid %s, %.2f s" % (
                      name, seed, r["coverage"], r["baseline_coverage"], r["removed_to_out"],
                      r["baseline_removed_to_out"], r["added_outside_holes"], r["baseline_added_outside_holes"],
                      r["free_space_violations"], r["baseline_free_space_violations"],
                      "kept" if r["kept_grid"] else "LOST", r["seconds"]), flush=True)
    write_csv(a.out / "holes.csv", rows)
    md = ["| frame | seed | removed | coverage ours / baseline | removed→out (s) ours / baseline | added ours / "
          "baseline | added outside the holes | free-space violations | W×H kept | seconds ours / baseline |",
          "|---|---:|---:|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %d | %d | %.4f / %.4f | %.3f / %.3f | %d / %d | %d / %d | %d / %d | %s | %.2f / %.2f |" % (
            r["frame"], r["seed"], r["removed"], r["coverage"], r["baseline_coverage"], r["removed_to_out"],
            r["baseline_removed_to_out"], r["added"], r["baseline_added"], r["added_outside_holes"],
            r["baseline_added_outside_holes"], r["free_space_violations"], r["baseline_free_space_violations"],
            "yes" if r["kept_grid"] else "**no**", r["seconds"], r["baseline_seconds"]))
    md += ["", "Per-frame means:", "",
           "| frame | coverage ours / baseline | removed→out (s) ours / baseline | added outside ours / baseline | "
           "free-space violations ours / baseline |", "|---|---|---|---|---|"]
    for name in frames:
        sel = [r for r in rows if r["frame"] == name]

        def mean(key):
            return float(np.mean([r[key] for r in sel]))
        md.append("| %s | %.4f / %.4f | %.3f / %.3f | %.1f / %.1f | %.1f / %.1f |" % (
            name, mean("coverage"), mean("baseline_coverage"), mean("removed_to_out"),
            mean("baseline_removed_to_out"), mean("added_outside_holes"), mean("baseline_added_outside_holes"),
            mean("free_space_violations"), mean("baseline_free_space_violations")))
    return md, rows


def whole_step(a, work, frames):
    rows, denoised = [], {}
    for name in frames:
        arr, W, H, _, src = load_frame(a, work, name)
        P_in = xyz(arr)
        row = {"frame": name, "width_x_height": "%d×%d" % (W, H), "points": int(finite_rows(P_in).sum())}
        for command in ("fill-holes", "denoise"):
            out = work / ("%s_%s.pcd" % (name, command))
            seconds, _ = run(a.log, [a.tool, command, src, "-o", out, "--json"])
            out_arr, out_info = read_pcd(out, work)
            changed, violations = whole_frame_check(P_in, W, H, xyz(out_arr))
            key = command.replace("-", "_")
            row.update({key + "_seconds": round(seconds, 3), key + "_not_input_points": changed,
                        key + "_free_space_violations": violations,
                        key + "_kept_grid": int((out_info["width"], out_info["height"]) == (W, H))})
            if command == "denoise":
                denoised[name] = (out, seconds)
        rows.append(row)
        print("whole  %-18s fill-holes %.2f s, %d added, %d free-space, grid %d; denoise %.2f s, %d moved, "
              "%d free-space, grid %d" % (
                  name, row["fill_holes_seconds"], row["fill_holes_not_input_points"],
                  row["fill_holes_free_space_violations"], row["fill_holes_kept_grid"], row["denoise_seconds"],
                  row["denoise_not_input_points"], row["denoise_free_space_violations"], row["denoise_kept_grid"]),
              flush=True)
    write_csv(a.out / "whole.csv", rows)
    md = ["| frame | W×H | points | `fill-holes` s | added | free-space violations | W×H kept | `denoise` s | "
          "points moved | free-space violations | W×H kept |", "|---|---|---:|---:|---:|---:|---|---:|---:|---:|---|"]
    for r in rows:
        md.append("| %s | %s | %d | %.2f | %d | %d | %s | %.2f | %d | %d | %s |" % (
            r["frame"], r["width_x_height"], r["points"], r["fill_holes_seconds"], r["fill_holes_not_input_points"],
            r["fill_holes_free_space_violations"], "yes" if r["fill_holes_kept_grid"] else "**no**",
            r["denoise_seconds"], r["denoise_not_input_points"], r["denoise_free_space_violations"],
            "yes" if r["denoise_kept_grid"] else "**no**"))
    return md, rows, denoised


def roughness_clouds(a, work, name, src, denoised, radii):
    """-> [(key, path, seconds)] of the clouds to score: the input, `denoise`, MLS at each radius."""
    env = dict(os.environ, OMP_NUM_THREADS="2")
    clouds = [("input", src, 0.0), ("denoise",) + denoised[name]]
    for radius in radii:
        mls = work / ("%s_mls%g.pcd" % (name, radius))
        seconds, _ = run(a.log, ["pcl_mls_smoothing", src, mls, "-radius", radius], env=env)
        clouds.append(("mls_%g" % radius, mls, seconds))
    return clouds


def roughness_step(a, work, frames, denoised, radii):
    rows = []
    for name in frames:
        arr, W, H, _, src = load_frame(a, work, name)
        P_in = xyz(arr)
        P0 = P_in[finite_rows(P_in)]
        ground, wall = ground_and_wall(P0)
        row = {"frame": name, "ground_tilt_deg": round(tilt_degrees(ground), 2),
               "wall_tilt_deg": round(tilt_degrees(wall), 2)}
        for key, path, seconds in roughness_clouds(a, work, name, src, denoised, radii):
            out_arr, out_info = read_pcd(path, work)
            P = xyz(out_arr)
            P = P[finite_rows(P)]
            g, w = plane_points(P, ground), plane_points(P, wall, ground)
            row.update({key + "_ground_mm": round(local_rms_mm(g), 4), key + "_ground_points": len(g),
                        key + "_wall_mm": round(local_rms_mm(w), 4), key + "_wall_points": len(w),
                        key + "_seconds": round(seconds, 2), key + "_points": len(P)})
            if key.startswith("mls"):
                changed, violations = whole_frame_check(P_in, W, H, P)
                row.update({key + "_free_space_violations": violations,
                            key + "_kept_grid": int((out_info["width"], out_info["height"]) == (W, H))})
        mls = ["mls_%g" % r for r in radii]
        for surface in ("ground", "wall"):  # MLS's best radius among those keeping half the region's points
            kept = [k for k in mls if row[k + "_%s_points" % surface] >= 0.5 * row["input_%s_points" % surface]]
            best = min(kept or mls, key=lambda k: row[k + "_%s_mm" % surface])
            row["mls_best_%s_radius_m" % surface] = float(best[4:])
            row["mls_best_%s_mm" % surface] = row[best + "_%s_mm" % surface]
        rows.append(row)
        print("rough  %-18s ground " % name + ", ".join("%s %.2f" % (k, row[k + "_ground_mm"]) for k in
                                                       ["input", "denoise"] + mls) + " mm; wall " +
              ", ".join("%s %.2f" % (k, row[k + "_wall_mm"]) for k in ["input", "denoise"] + mls) + " mm",
              flush=True)
    write_csv(a.out / "roughness.csv", rows)
    return roughness_md(rows, radii), rows


def roughness_md(rows, radii):
    mls = ["mls_%g" % r for r in radii]
    md = []
    for surface in ("ground", "wall"):
        md += ["", "**%s** (mm; points in the region in brackets):" % surface.capitalize(), "",
               "| frame | tilt ° | input | `denoise` | " + " | ".join("MLS %g m" % r for r in radii) +
               " | MLS best radius |", "|---|---:|---:|---:|" + "---:|" * len(radii) + "---:|"]
        for r in rows:
            md.append("| %s | %.1f | %s |" % (r["frame"], r[surface + "_tilt_deg"], " | ".join(
                "%.2f (%d)" % (r["%s_%s_mm" % (k, surface)], r["%s_%s_points" % (k, surface)])
                for k in ["input", "denoise"] + mls)) + " %g m |" % r["mls_best_%s_radius_m" % surface])
    md += ["", "MLS outputs: free-space violations / grid kept / points / seconds:", "",
           "| frame | " + " | ".join("MLS %g m" % r for r in radii) + " |", "|---|" + "---|" * len(radii)]
    for r in rows:
        md.append("| %s | " % r["frame"] + " | ".join("%d / %s / %d / %.1f s" % (
            r[k + "_free_space_violations"], "yes" if r[k + "_kept_grid"] else "no", r[k + "_points"],
            r[k + "_seconds"]) for k in mls) + " |")
    return md


def rate_step(a, frames):
    rows = []
    program = a.tool.parent / "bench" / "frame_rate"
    if not program.exists():
        print("rate   %s not built — skipped" % program)
        return ["(frame_rate not built — skipped)"], rows
    for name in frames:
        path = a.frames_dir / (name + ".pcd")
        if not path.exists():
            print("rate   %s absent — skipped" % path)
            continue
        row = {"frame": name}
        for threads in (1, 2):
            _, text = run(a.log, [program, path, "--frames", 20, "--threads", threads, "--json"])
            result = json.loads(text.strip().splitlines()[-1])
            row.update({"ms_per_frame_%dt" % threads: result["ms_per_frame"], "hz_%dt" % threads: result["hz"],
                        "points_added_%dt" % threads: result.get("points_added", "")})
            row["sensor"] = result.get("sensor", "")
        rows.append(row)
        print("rate   %-20s %s: %.1f ms (1 thread), %.1f ms (2 threads)" % (
            name, row["sensor"], row["ms_per_frame_1t"], row["ms_per_frame_2t"]), flush=True)
    write_csv(a.out / "rate.csv", rows)
    md = ["| frame | sensor | ms/frame 1 thread | ms/frame 2 threads | Hz 1 / 2 threads |", "|---|---|---:|---:|---|"]
    for r in rows:
        md.append("| %s | %s | %.1f | %.1f | %.1f / %.1f |" % (r["frame"], r["sensor"], r["ms_per_frame_1t"],
                                                              r["ms_per_frame_2t"], r["hz_1t"], r["hz_2t"]))
    return md, rows


def acceptance(holes, whole, rough):
    """The project's acceptance lines. -> list of misses (empty when all are met)."""
    miss = []
    for r in holes:
        case = "%s seed %d" % (r["frame"], r["seed"])
        if r["coverage"] < 0.99:
            miss.append("%s: coverage %.4f < 0.99" % (case, r["coverage"]))
        if r["removed_to_out"] > r["baseline_removed_to_out"] + 0.05:
            miss.append("%s: removed→out %.3f > baseline %.3f + 0.05" % (case, r["removed_to_out"],
                                                                        r["baseline_removed_to_out"]))
        if r["free_space_violations"]:
            miss.append("%s: %d free-space violations" % (case, r["free_space_violations"]))
        if not r["kept_grid"]:
            miss.append("%s: width × height not kept" % case)
        if r["added_outside_holes"] > 1.5 * r["baseline_added_outside_holes"]:
            miss.append("%s: %d added outside the holes > 1.5 × baseline's %d" % (
                case, r["added_outside_holes"], r["baseline_added_outside_holes"]))
    for r in whole:
        for key in ("fill_holes", "denoise"):
            if r[key + "_free_space_violations"] or not r[key + "_kept_grid"]:
                miss.append("%s whole `%s`: %d free-space violations, grid kept %d" % (
                    r["frame"], key.replace("_", "-"), r[key + "_free_space_violations"], r[key + "_kept_grid"]))
    for r in rough:
        for surface in ("ground", "wall"):
            ours, base = r["denoise_%s_mm" % surface], r["input_%s_mm" % surface]
            if not ours < base:
                miss.append("%s: `denoise` %s roughness %.3f mm not below the input's %.3f" % (
                    r["frame"], surface, ours, base))
    return miss


def header(a, seconds, steps, commit):
    return ["# Spinning LiDAR frames", "",
            "*`bench/spinning_scans.py%s`, commit %s, %s UTC, %.0f s (steps %s s); `%s` built %s UTC; frames "
            "from `%s`.*" % (" --quick" if a.quick else "", commit, time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                             seconds, " / ".join("%.0f" % s for s in steps), a.tool.name,
                             time.strftime("%Y-%m-%d %H:%M", time.gmtime(a.tool.stat().st_mtime)), a.frames_dir),
            "", "s is the local spacing (median distance to the 4 nearest input points). Added: output points that "
            "are not input points (to 1e-6 of the extent). Free-space violation: an added point nearer the origin "
            "than the minimum measured range of the 3×3 beams around its nearest beam direction by more than "
            "max(3 s, 1 % of that range) (azimuth wraps, beams do not). Seconds: wall time of the whole command "
            "on a shared 2-core machine."]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--seeds", default="1,2,3")
    parser.add_argument("--frames-dir", default=str(ROOT.parent / "shared" / "data" / "real"))
    parser.add_argument("--tool", default=str(ROOT / "build" / "pcl_patchdict"))
    parser.add_argument("--out", default=str(ROOT / "build" / "spinning_scans"))
    parser.add_argument("--work", help="keep the intermediate clouds here (default: a temporary folder)")
    a = parser.parse_args()
    a.frames_dir, a.tool, a.out = Path(a.frames_dir).resolve(), Path(a.tool).resolve(), Path(a.out).resolve()
    frames = [f for f in FRAMES if (a.frames_dir / (f + ".pcd")).exists()]
    if not frames:
        print("spinning_scans.py: no Ouster frames in %s — skipped" % a.frames_dir)
        return
    if not a.tool.exists():
        sys.exit("spinning_scans.py: %s not built — run scripts/build.sh first" % a.tool)
    for program in ("pcl_convert_pcd_ascii_binary", "pcl_mls_smoothing"):
        if shutil.which(program) is None:
            sys.exit("spinning_scans.py: %s not found (Debian's pcl-tools)" % program)
    seeds, radii = [int(s) for s in a.seeds.split(",") if s], MLS_RADII
    rate_frames = frames + [KINECT]
    if a.quick:
        frames, seeds, radii = frames[:1], seeds[:1], [0.1, 0.3]
        rate_frames = frames
    a.out.mkdir(parents=True, exist_ok=True)
    a.keep = a.work is not None
    work = Path(a.work).resolve() if a.keep else Path(tempfile.mkdtemp(prefix="spinning_scans_"))
    work.mkdir(parents=True, exist_ok=True)
    a.log = a.out / "spinning_scans.log"
    a.log.write_text("# spinning_scans.py %s\n" % " ".join(sys.argv[1:]))
    start, steps = time.monotonic(), []
    try:
        t = time.monotonic()
        holes_md, holes = holes_step(a, work, frames, seeds)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        whole_md, whole, denoised = whole_step(a, work, frames)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        rough_md, rough = roughness_step(a, work, frames, denoised, radii)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        rate_md, _ = rate_step(a, rate_frames)
        steps.append(time.monotonic() - t)
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    miss = acceptance(holes, whole, rough)
    write_summary(a, time.monotonic() - start, steps, holes_md, whole_md, rough_md, rate_md, miss)
    print("spinning_scans.py: wrote %s in %.0f s; acceptance: %s" % (
        a.out / "spinning_scans.md", time.monotonic() - start, "all met" if not miss else "%d MISSED" % len(miss)))
    for m in miss:
        print("  MISS " + m)


def write_summary(a, seconds, steps, holes_md, whole_md, rough_md, rate_md, miss):
    tool = "pcl_patchdict"
    md = header(a, seconds, steps, git_commit()) + [
        "", "### 1. Punched holes", "",
        "8 discs per case in the range image (2–4 px on 32 beams, 3–8 px on 128), each on one surface (disc and "
        "2-px ring valid, range spread < 3 %%, off the first and last 2 beams), `numpy.random.default_rng(seed)`; "
        "the removed real points are the truth. Command: `%s fill-holes holed.pcd -o out.pcd --json`. Baseline: "
        "this script's harmonic range-image fill (every enclosed NaN region of ≤ 2000 px, azimuth wrapping, not "
        "touching the first or last beam, rim range spread < 3 %%; Laplace in range and in the unit direction; "
        "timed in-process). In a hole: nearest measured beam within 1.5 px of a disc." % tool, ""] + holes_md + [
        "", "### 2. Whole frames", "",
        "Commands: `%s fill-holes FRAME.pcd -o OUT.pcd --json` and `%s denoise FRAME.pcd -o OUT.pcd --json` "
        "(FRAME converted to binary). For `denoise`, every moved point counts as added in the free-space test."
        % (tool, tool), ""] + whole_md + [
        "", "### 3. Denoising roughness: the ground and the largest wall", "",
        "Ground: RANSAC on the input (500 tries, `default_rng(0)`, points within 0.1 m); wall: the same on the "
        "input's points more than 0.5 m above the ground (tilt: the normal's angle to vertical). For each "
        "cloud, its points within 0.1 m of the plane (wall: and > 0.5 m above the ground); 4000 of them "
        "(`default_rng(1)`) each get a plane fitted to their 0.5 m neighbourhood (≥ 10 points); the RMS of "
        "the residuals, mm. MLS: `OMP_NUM_THREADS=2 pcl_mls_smoothing FRAME.pcd MLS.pcd -radius R` (PCL's "
        "defaults; it drops points with too few neighbours). MLS best radius: the lowest roughness among the "
        "radii keeping at least half the input's points of the region."] + rough_md + [
        "", "### 4. Frame rate", "",
        "`build/bench/frame_rate FRAME --frames 20 --threads T --json`: ms per frame (ms_per_frame)."] + [""] + rate_md
    met = ["All met: coverage ≥ 0.99, removed→out ≤ baseline + 0.05 s, 0 free-space violations, W×H kept, "
           "added outside ≤ 1.5 × baseline's, whole frames 0 violations, `denoise` below the input on ground and "
           "wall."]
    md += ["", "### Acceptance", ""] + (met if not miss else ["**Missed:**", ""] + ["- " + m for m in miss]) + [""]
    (a.out / "spinning_scans.md").write_text("\n".join(md))


if __name__ == "__main__":
    main()
