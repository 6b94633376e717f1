#!/usr/bin/env python3
"""The paper's Fig. 7 on the bunny: mean point-to-mesh error of the reconstructed vertices against
the number of atoms of a local dictionary coded with 20 non-zeros (Sarkar et al. 2017, section 5).

Runs the built tool: `patches` (N = 16, L = 0.03, overlap 1) -> `learn` (K-SVD, K atoms, sparsity
min(20, K)) -> `reconstruct --dict` (encode with min(20, K) atoms, decode, bilinear rule on the
original connectivity). The error is `vertex_to_surface_mean` of `reconstruct --json`: the mean
distance of the reconstructed vertices to the original surface, in unit-cube units.
Writes bench/results/fig7_atoms.csv and bench/results/fig7_atoms.png (python3 standard library only).

usage: bench/fig7_atoms.py [--tool build/pcl_patchdict] [--mesh data/bunny.obj] [--iterations 10]
                           [--threads 2] [--atoms 5,10,20,50,100,200,500] [--plot-only]
(about 6 min on 2 busy cores; the y axis is linear from 0, the x axis logarithmic, the dashed
line is the identity round trip)
"""
import argparse
import csv
import json
import math
import os
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def run(tool, *args):
    result = subprocess.run([tool, *args], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("failed: %s %s\n%s" % (tool, " ".join(args), result.stderr))
    return json.loads(result.stdout) if "--json" in args else None


# ---------------------------------------------------------------- a minimal plot
# 3×5 glyphs for tick labels and the caption (rows top to bottom, 3 bits each).
GLYPHS = {
    "0": "111101101101111", "1": "010110010010111", "2": "111001111100111", "3": "111001111001111",
    "4": "101101111001001", "5": "111100111001111", "6": "111100111101111", "7": "111001001001001",
    "8": "111101111101111", "9": "111101111001111", ".": "000000000000010", "-": "000000111000000",
    "e": "000111101110111", "+": "000010111010000", " ": "000000000000000",
}


class Canvas:
    def __init__(self, width, height):
        self.width, self.height = width, height
        self.pixels = bytearray([255] * (width * height * 3))

    def set(self, x, y, colour):
        if 0 <= x < self.width and 0 <= y < self.height:
            i = (y * self.width + x) * 3
            self.pixels[i:i + 3] = bytes(colour)

    def line(self, x0, y0, x1, y1, colour, dash=0, thick=1):
        steps = max(abs(x1 - x0), abs(y1 - y0), 1)
        for s in range(steps + 1):
            if dash and (s // dash) % 2:
                continue
            x = round(x0 + (x1 - x0) * s / steps)
            y = round(y0 + (y1 - y0) * s / steps)
            for dx in range(thick):
                for dy in range(thick):
                    self.set(x + dx - thick // 2, y + dy - thick // 2, colour)

    def text(self, x, y, string, colour=(0, 0, 0), scale=2):
        for c in string:
            glyph = GLYPHS.get(c, GLYPHS[" "])
            for row in range(5):
                for col in range(3):
                    if glyph[row * 3 + col] == "1":
                        for dx in range(scale):
                            for dy in range(scale):
                                self.set(x + col * scale + dx, y + row * scale + dy, colour)
            x += 4 * scale

    def png(self, path):
        raw = b"".join(b"\x00" + bytes(self.pixels[y * self.width * 3:(y + 1) * self.width * 3])
                       for y in range(self.height))

        def chunk(kind, data):
            return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

        header = struct.pack(">IIBBBBB", self.width, self.height, 8, 2, 0, 0, 0)
        with open(path + ".tmp", "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) +
                    chunk(b"IEND", b""))
        os.replace(path + ".tmp", path)


def plot(path, atoms, errors, identity):
    """Error (y, linear from 0) against atoms (x, log scale); dashed grey: the identity round trip."""
    width, height, left, right, top, bottom = 720, 480, 110, 30, 30, 60
    canvas = Canvas(width, height)
    x_lo, x_hi = math.log10(min(atoms)) - 0.1, math.log10(max(atoms)) + 0.1
    y_hi = max(errors) * 1.1
    px = lambda a: round(left + (math.log10(a) - x_lo) / (x_hi - x_lo) * (width - left - right))
    py = lambda e: round(height - bottom - e / y_hi * (height - top - bottom))
    black, grey, blue = (0, 0, 0), (150, 150, 150), (30, 80, 200)
    canvas.line(left, height - bottom, width - right, height - bottom, black)
    canvas.line(left, top, left, height - bottom, black)
    for a in atoms:
        canvas.line(px(a), height - bottom, px(a), height - bottom + 6, black)
        label = str(a)
        canvas.text(px(a) - len(label) * 4, height - bottom + 12, label)
    for i in range(6):
        e = y_hi * i / 5
        canvas.line(left - 6, py(e), left, py(e), black)
        canvas.line(left + 1, py(e), width - right, py(e), (225, 225, 225))
        label = "%.1e" % e
        canvas.text(left - 10 - len(label) * 8, py(e) - 5, label)
    canvas.line(left + 1, py(identity), width - right, py(identity), grey, dash=6)
    for (a0, e0), (a1, e1) in zip(zip(atoms, errors), zip(atoms[1:], errors[1:])):
        canvas.line(px(a0), py(e0), px(a1), py(e1), blue, thick=2)
    for a, e in zip(atoms, errors):
        for dx in range(-3, 4):
            for dy in range(-3, 4):
                canvas.set(px(a) + dx, py(e) + dy, blue)
    canvas.png(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tool", default=os.path.join(ROOT, "build", "pcl_patchdict"))
    parser.add_argument("--mesh", default=os.path.join(ROOT, "data", "bunny.obj"))
    parser.add_argument("--iterations", default="10", help="K-SVD iterations")
    parser.add_argument("--threads", default="2")
    parser.add_argument("--atoms", default="5,10,20,50,100,200,500")
    parser.add_argument("--out", default=os.path.join(HERE, "results", "fig7_atoms"))
    parser.add_argument("--plot-only", action="store_true", help="redraw the PNG from an existing CSV")
    args = parser.parse_args()
    if args.plot_only:
        with open(args.out + ".csv") as f:
            table = [row for row in csv.DictReader(f)]
        coded = [row for row in table if int(row["atoms"]) > 0]
        identity_error = [float(row["vertex_to_surface_mean"]) for row in table if int(row["atoms"]) == 0][0]
        plot(args.out + ".png", [int(r["atoms"]) for r in coded], [float(r["vertex_to_surface_mean"]) for r in coded],
             identity_error)
        return
    atoms = [int(a) for a in args.atoms.split(",")]
    common = ["--threads", args.threads, "--quiet"]
    rows = []
    with tempfile.TemporaryDirectory() as work:
        pds, out = os.path.join(work, "patches.pds"), os.path.join(work, "out.ply")
        run(args.tool, "patches", args.mesh, "-o", pds, "--grid", "16", "--quad-length", "0.03", *common)
        identity = run(args.tool, "reconstruct", args.mesh, "-o", out, "--json", *common)
        print("identity: vertex-to-surface mean %.4e, PSNR %.2f dB" % (identity["vertex_to_surface_mean"],
                                                                     identity["psnr_db"]), flush=True)
        for k in atoms:
            sparsity = str(min(20, k))
            pdd = os.path.join(work, "d%d.pdd" % k)
            learned = run(args.tool, "learn", pds, "-o", pdd, "--atoms", str(k), "--sparsity", sparsity,
                          "--iterations", args.iterations, "--json", *common)
            coded = run(args.tool, "reconstruct", args.mesh, "-o", out, "--dict", pdd, "--sparsity", sparsity,
                        "--json", *common)
            rows.append([k, int(sparsity), coded["vertex_to_surface_mean"], coded["vertex_rmse"], coded["psnr_db"],
                         coded["patch_rmse"], learned["seconds"]["learn"]])
            print("atoms %4d, sparsity %2s: vertex-to-surface mean %.4e, vertex RMSE %.4e, PSNR %.2f dB, "
                  "patch RMSE %.3e (learning %.1f s)" % tuple(rows[-1]), flush=True)
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out + ".csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["atoms", "sparsity", "vertex_to_surface_mean", "vertex_rmse", "psnr_db", "patch_rmse",
                         "learn_seconds"])
        writer.writerow([0, 0, identity["vertex_to_surface_mean"], identity["vertex_rmse"], identity["psnr_db"], 0, 0])
        writer.writerows(rows)
    plot(args.out + ".png", [r[0] for r in rows], [r[2] for r in rows], identity["vertex_to_surface_mean"])
    print("wrote %s.csv and %s.png (row atoms = 0: the identity round trip)" % (args.out, args.out))


if __name__ == "__main__":
    main()
