#!/usr/bin/env python3
"""Compression: the paper's Table 1 and a rate-distortion curve beside Draco (Sarkar et al. 2017, 5.2).

1. A global dictionary (100 atoms, K-SVD, sparsity 10) learned from 16x16 patches of side 0.08 on six
   shapes of ../shared/data/meshes that are NOT compressed below (chinese_dragon, happy_buddha,
   mountain, skull, boot, demosthenes): `patches` + `learn`, cached in the output folder.
2. For each of bunny, fandisk, armadillo, lucy, max_planck: `compress --json` at quad lengths L from
   --lengths (patch side 1.25 L, 20 coefficients per patch, 6-bit coefficients, 10-bit quad
   vertices, coverage patches where the quads miss the surface by more than 0.1 L); bytes of the .pdc
   file, the paper's entity count, and PSNR = 20 log10(bbox diagonal / symmetric RMS surface distance)
   of the decoded mesh (200k samples each way, as the harness does). Each L with five settings
   (VARIANTS): the defaults; an error target of 0.025 L (`--target-error`: at most 20 non-zeros, fewer
   where a patch is already coded that well); one price per atom, 0.02 L² and 0.08 L² (`--atom-cost`:
   each patch keeps the number of atoms that minimises its squared error plus the price per atom); and no coverage
   patches (`--coverage-tolerance 0`).
3. Draco (`draco_encoder -cl 7 -qp Q`, Q in --draco-bits) on the same meshes, decoded by
   `draco_decoder` and scored by `pcl_patchdict eval` (the same PSNR).

Writes <out>.csv (every point), <out>.png (PSNR against bytes, log scale, one panel per mesh: blue
ours with the defaults, green with the 0.025 L error target, purple at the 0.02 L² atom price, grey
without coverage patches, red
Draco) and <out>_table1.md (Table 1: for each mesh the setting with the largest entity factor at or
above the paper's PSNR, and Draco's bytes at that PSNR, interpolated on its curve).
Needs the `draco` Debian package (installed here with apt-get when missing and run as root).

usage: bench/codec_rate_distortion.py [--tool build/pcl_patchdict] [--meshes DIR] [--out PREFIX]
       [--lengths 0.12,0.1,...,0.032] [--draco-bits 6,7,8,9,10,11,12,14] [--plot-only]
(8 min on 2 idle cores, measured at d4bc401)
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from fig7_atoms import Canvas  # noqa: E402  (the same dependency-free PNG plot)

TRAINING = ["chinese_dragon.off", "happy_buddha.obj", "mountain.obj", "skull.obj", "boot.obj", "demosthenes.obj"]
TESTED = ["bunny", "fandisk", "armadillo", "lucy", "max_planck"]
# Table 1 of the paper: compression factor (entities) and PSNR; scans not in it get the scans' bar.
PAPER = {"bunny": (31.3, 60.6), "fandisk": (3.9, 62.1)}
SCAN_BAR = (28.0, 56.0)
# Our settings at each L: the defaults (coverage patches at 0.1 L, 20 non-zeros per patch); a per-patch
# error target that stops taking atoms once a patch is coded well enough (0.025 L); one price per atom
# for every patch (0.02 L², 0.08 L²), which puts the atoms where they remove the most error; and no
# coverage patches, to show what they add.
VARIANTS = [("patchdict", []), ("patchdict-e0.025", ["--target-error", "0.025"]),
            ("patchdict-c0.02", ["--atom-cost", "0.02"]), ("patchdict-c0.08", ["--atom-cost", "0.08"]),
            ("patchdict-nocov", ["--coverage-tolerance", "0"])]


def run(*command, parse=True):
    result = subprocess.run(list(command), capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(command), result.stderr))
    return json.loads(result.stdout) if parse else None


def ensure_draco():
    if shutil.which("draco_encoder"):
        return
    if os.geteuid() == 0:
        subprocess.run(["apt-get", "install", "-y", "draco"], check=False, capture_output=True)
    if not shutil.which("draco_encoder"):
        sys.exit("draco_encoder not found: apt-get install draco")


def global_dictionary(tool, meshes, work, training=TRAINING):
    pdd = os.path.join(work, "global_100_%d.pdd" % len(training))
    if os.path.exists(pdd):
        return pdd
    sets = []
    for name in training:
        pds = os.path.join(work, "train_%s.pds" % os.path.splitext(name)[0])
        run(tool, "patches", os.path.join(meshes, name), "-o", pds, "--quad-length", "0.08", "--grid", "16",
            "--quiet", parse=False)
        sets.append(pds)
    # K-SVD, as the figures were made (several inputs would default to online learning).
    run(tool, "learn", *sets, "-o", pdd, "--method", "ksvd", "--atoms", "100", "--sparsity", "10", "--quiet",
        parse=False)
    return pdd


def plot(path, rows):
    panels = [m for m in TESTED if any(r["mesh"] == m for r in rows)]
    columns, panel_w, panel_h = 3, 420, 300
    canvas = Canvas(columns * panel_w, ((len(panels) + columns - 1) // columns) * panel_h)
    blue, red, black = (30, 80, 200), (200, 40, 40), (0, 0, 0)
    for index, mesh in enumerate(panels):
        ox, oy = (index % columns) * panel_w, (index // columns) * panel_h
        left, right, top, bottom = ox + 60, ox + panel_w - 15, oy + 20, oy + panel_h - 40
        points = [r for r in rows if r["mesh"] == mesh]
        xs = [math.log10(float(r["bytes"])) for r in points]
        ys = [float(r["psnr"]) for r in points]
        x_lo, x_hi = math.floor(min(xs) * 2) / 2, math.ceil(max(xs) * 2) / 2
        y_lo, y_hi = math.floor(min(ys) / 10) * 10, math.ceil(max(ys) / 10) * 10
        px = lambda x: round(left + (x - x_lo) / (x_hi - x_lo) * (right - left))
        py = lambda y: round(bottom - (y - y_lo) / (y_hi - y_lo) * (bottom - top))
        canvas.line(left, bottom, right, bottom, black)
        canvas.line(left, top, left, bottom, black)
        x = x_lo
        while x <= x_hi + 1e-9:
            canvas.line(px(x), bottom, px(x), bottom + 5, black)
            label = "%g" % (10 ** x) if abs(x - round(x)) < 1e-9 else ""
            canvas.text(px(x) - len(label) * 4, bottom + 10, label)
            x += 0.5
        for y in range(int(y_lo), int(y_hi) + 1, 10):
            canvas.line(left - 5, py(y), left, py(y), black)
            canvas.line(left + 1, py(y), right, py(y), (225, 225, 225))
            canvas.text(left - 30, py(y) - 5, str(y))
        for method, colour in (("patchdict-nocov", (160, 160, 160)), ("patchdict-e0.025", (40, 160, 60)),
                               ("patchdict-c0.02", (150, 60, 170)), ("patchdict", blue), ("draco", red)):
            series = sorted((math.log10(float(r["bytes"])), float(r["psnr"])) for r in points if r["method"] == method)
            for (x0, y0), (x1, y1) in zip(series, series[1:]):
                canvas.line(px(x0), py(y0), px(x1), py(y1), colour, thick=2)
            for x, y in series:
                for dx in range(-3, 4):
                    for dy in range(-3, 4):
                        canvas.set(px(x) + dx, py(y) + dy, colour)
        canvas.text(left + 10, top + 2, str(index + 1))
    canvas.png(path)


def draco_bytes_at(rows, mesh, psnr):
    """Draco's bytes at the given PSNR, interpolated linearly in log(bytes) on its curve (None outside)."""
    series = sorted((float(r["psnr"]), math.log10(float(r["bytes"]))) for r in rows
                    if r["mesh"] == mesh and r["method"] == "draco")
    for (p0, b0), (p1, b1) in zip(series, series[1:]):
        if p0 <= psnr <= p1 and p1 > p0:
            return 10 ** (b0 + (psnr - p0) / (p1 - p0) * (b1 - b0))
    return None


def table1(path, rows):
    lines = ["| mesh | setting | L | patches (coverage) | mesh entities | patch entities | factor (entities) | paper factor* | "
             "bytes | factor (bytes) | PSNR | paper PSNR* | met | Draco bytes at this PSNR |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for mesh in [m for m in TESTED if any(r["mesh"] == m for r in rows)]:
        paper_factor, paper_psnr = PAPER.get(mesh, SCAN_BAR)
        ours = [r for r in rows if r["mesh"] == mesh and r["method"].startswith("patchdict") and
                float(r["psnr"]) >= paper_psnr]
        if not ours:
            lines.append("| %s | no setting reaches %.1f dB | | | | | | %.1f | | | | %.1f | no | |" %
                         (mesh, paper_psnr, paper_factor, paper_psnr))
            continue
        best = max(ours, key=lambda r: float(r["entity_factor"]))
        draco = draco_bytes_at(rows, mesh, float(best["psnr"]))
        met = float(best["entity_factor"]) >= paper_factor
        lines.append("| %s | %s | %s | %s (%s) | %s | %s | %.2f | %.1f | %s | %.1f | %.2f | %.1f | %s | %s |" % (
            mesh, best["method"], best["setting"], best["patches"], best.get("coverage_patches", ""), best["mesh_entities"],
            best["patch_entities"], float(best["entity_factor"]), paper_factor, best["bytes"],
            float(best["byte_factor"]), float(best["psnr"]), paper_psnr, "yes" if met else "no",
            "%.0f" % draco if draco else "outside Draco's curve"))
    lines.append("")
    lines.append("\\* bunny and fandisk: the paper's Table 1; the other meshes are not in it and are held to %.0f× "
                 "and %.0f dB, about the weakest of the paper's scan rows (Baseball 27.7×, Totem 56.6 dB)." % SCAN_BAR)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tool", default=os.path.join(ROOT, "build", "pcl_patchdict"))
    parser.add_argument("--meshes", default=os.path.join(ROOT, "..", "shared", "data", "meshes"))
    parser.add_argument("--out", default=os.path.join(HERE, "results", "codec_rd"))
    parser.add_argument("--lengths", default="0.12,0.1,0.09,0.085,0.08,0.075,0.07,0.064,0.056,0.05,0.045,0.04,0.032")
    parser.add_argument("--draco-bits", default="6,7,8,9,10,11,12,14")
    parser.add_argument("--plot-only", action="store_true", help="redraw PNG and table from an existing CSV")
    parser.add_argument("--quick", action="store_true",
                        help="CI smoke: fandisk only, L 0.08 and 0.05, the defaults and no coverage, Draco q8 and "
                             "q11, dictionary from 2 shapes")
    args = parser.parse_args()
    tested, training, variants = TESTED, TRAINING, VARIANTS
    if args.quick:
        tested, training = ["fandisk"], ["boot.obj", "demosthenes.obj"]
        args.lengths, args.draco_bits = "0.08,0.05", "8,11"
        variants = [VARIANTS[0], VARIANTS[-1]]
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    fields = ["mesh", "method", "setting", "bytes", "psnr", "rms", "patches", "coverage_patches", "mesh_entities",
              "patch_entities", "entity_factor", "byte_factor", "seconds"]
    if args.plot_only:
        with open(args.out + ".csv") as f:
            rows = list(csv.DictReader(f))
    else:
        ensure_draco()
        rows = []
        cache = os.path.join(os.path.dirname(args.out), "codec_work")
        os.makedirs(cache, exist_ok=True)
        pdd = global_dictionary(args.tool, args.meshes, cache, training)
        with tempfile.TemporaryDirectory() as work:
            for mesh in tested:
                source = os.path.join(args.meshes, mesh + ".obj")
                for length in args.lengths.split(","):
                    for method, extra in variants:
                        pdc = os.path.join(work, "m.pdc")
                        r = run(args.tool, "compress", source, "--dict", pdd, "-o", pdc, "--quad-length", length,
                                *extra, "--json")
                        rows.append(dict(mesh=mesh, method=method, setting=length, bytes=r["bytes"], psnr=r["psnr"],
                                         rms=r["rms"], patches=r["patches"], coverage_patches=r["coverage_patches"],
                                         mesh_entities=r["mesh_entities"], patch_entities=r["patch_entities"],
                                         entity_factor=r["entity_factor"], byte_factor=r["byte_factor"],
                                         seconds=r["seconds"]["encode"]))
                        print("%-10s %-16s L %-5s %7d bytes  %5.1f x entities  %6.1f x bytes  PSNR %.2f dB" % (
                            mesh, method, length, r["bytes"], r["entity_factor"], r["byte_factor"], r["psnr"]),
                            flush=True)
                for bits in args.draco_bits.split(","):
                    drc, out = os.path.join(work, "m.drc"), os.path.join(work, "m_draco.ply")
                    run("draco_encoder", "-i", source, "-o", drc, "-cl", "7", "-qp", bits, parse=False)
                    run("draco_decoder", "-i", drc, "-o", out, parse=False)
                    e = run(args.tool, "eval", source, out, "--json")
                    size = os.path.getsize(drc)
                    raw = 12.0 * (e["reference_vertices"] + e["reference_faces"])
                    rows.append(dict(mesh=mesh, method="draco", setting="q" + bits, bytes=size, psnr=e["psnr_db"],
                                     rms=e["surface"]["rms"], patches="", coverage_patches="", mesh_entities="",
                                     patch_entities="",
                                     entity_factor="", byte_factor=raw / size, seconds=""))
                    print("%-10s draco q%-3s %7d bytes  %6.1f x bytes  PSNR %.2f dB" % (
                        mesh, bits, size, raw / size, e["psnr_db"]), flush=True)
        with open(args.out + ".csv", "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=fields)
            writer.writeheader()
            writer.writerows(rows)
    plot(args.out + ".png", rows)
    print("\n".join(table1(args.out + "_table1.md", rows)))
    print("wrote %s.csv, %s.png and %s_table1.md" % (args.out, args.out, args.out))


if __name__ == "__main__":
    main()
