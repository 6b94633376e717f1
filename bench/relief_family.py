#!/usr/bin/python3
"""A family of grooved relief clouds with holes, and what the patches do on each (issue 37).

usage: /usr/bin/python3 bench/relief_family.py [--tool build/pcl_patchdict] [--harness ../shared/harness]
           [--work /tmp/relief_family] [--only REGEX]

Each member is a unit square of grooves: depth D, pitch P, direction theta (the MEMBERS table; the
holes are the harness's 12 discs of radius 0.035, so P runs from below to above the hole diameter
0.07). A groove is a flat-bottomed third of the pitch with smooth walls; the square is a 220 x 220
grid. The harness (a judge, not a dependency of the project: cases.py makes gt.ply and the cloud
cases, eval.py scores) punches the holes into a 100k-point sample; `fill-holes` runs with and
without patches; the table reports the inside error (rms of the filled points to the truth) with
patches over without, the coverage of the removed points (within 1.5 spacings) both ways, and the
patch decision. Members marked held-back are never used to choose a rule or a constant.
"""
import argparse
import json
import os
import re
import subprocess
import sys

import numpy as np

# name, depth, pitch, direction (degrees), held back
MEMBERS = [
    ("d4p03t0", 0.004, 0.03, 0, False), ("d4p06t0", 0.004, 0.06, 0, False), ("d4p12t0", 0.004, 0.12, 0, False),
    ("d10p03t0", 0.010, 0.03, 0, False), ("d10p06t0", 0.010, 0.06, 0, False), ("d10p12t0", 0.010, 0.12, 0, False),
    ("d4p06t30", 0.004, 0.06, 30, False), ("d10p12t30", 0.010, 0.12, 30, False),
    ("d7p09t45", 0.007, 0.09, 45, True), ("d14p16t15", 0.014, 0.16, 15, True),
]


def groove(t):
    """A flat-bottomed groove over the first third of the phase t in [0, 1), smooth walls."""
    w, e = 1.0 / 3.0, 0.06
    s = np.clip(t / e, 0, 1) * np.clip((w - t) / e, 0, 1)
    return 3 * s ** 2 - 2 * s ** 3


def write_relief(path, depth, pitch, theta, n=220):
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    u = x * np.cos(np.radians(theta)) + y * np.sin(np.radians(theta))
    z = -depth * groove(np.mod(u / pitch, 1.0))
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    faces = np.r_[np.c_[a, b, c], np.c_[a, c, d]]
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (n * n, len(faces)))
        np.savetxt(f, np.c_[x.ravel(), y.ravel(), z.ravel()], fmt="%.9g")
        np.savetxt(f, np.c_[np.full(len(faces), 3), faces], fmt="%d")


def last_json(path):
    lines = open(path).read().strip().splitlines()
    return json.loads(lines[-1]) if lines else {}


def run_member(args, name, depth, pitch, theta):
    case = os.path.join(args.work, "cases", name)
    if not os.path.isfile(os.path.join(case, "cloud_holes.ply")):
        mesh = os.path.join(args.work, name + ".ply")
        write_relief(mesh, depth, pitch, theta)
        subprocess.run(["/usr/bin/python3", os.path.join(args.harness, "cases.py"), mesh, "--out",
                        os.path.join(args.work, "cases")], check=True, capture_output=True)
    row = {}
    for mode, extra in (("patches", []), ("base", ["--no-patches"])):
        out = os.path.join(case, "out_%s.ply" % mode)
        report = subprocess.run([args.tool, "fill-holes", os.path.join(case, "cloud_holes.ply"), "-o", out, "--json",
                                 "--quiet"] + extra, check=True, capture_output=True, text=True).stdout
        score = subprocess.run(["/usr/bin/python3", os.path.join(args.harness, "eval.py"), "cloud-completion",
                                os.path.join(case, "gt.ply"), os.path.join(case, "cloud_holes_region.ply"), out],
                               check=True, capture_output=True, text=True).stdout
        s = json.loads(score.strip().splitlines()[-1])
        row[mode] = {"inside": s["inside"]["rms"], "coverage": s["coverage"]["within_1.5s"],
                     "patches": json.loads(report.strip().splitlines()[-1]).get("patches", {})}
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--tool", default=os.path.join(here, "..", "build", "pcl_patchdict"))
    ap.add_argument("--harness", default=os.path.join(here, "..", "..", "shared", "harness"))
    ap.add_argument("--work", default="/tmp/relief_family")
    ap.add_argument("--only", default="")
    args = ap.parse_args()
    if not os.path.isfile(os.path.join(args.harness, "eval.py")):
        sys.exit("relief_family: the harness (cases.py, eval.py) is not at %s (--harness)" % args.harness)
    os.makedirs(os.path.join(args.work, "cases"), exist_ok=True)
    print("| member | D | P | θ | inside, patches / none | coverage, patches / none | decision (gain, side) |")
    print("|---|---:|---:|---:|---|---|---|")
    for name, depth, pitch, theta, held in MEMBERS:
        if args.only and not re.search(args.only, name):
            continue
        r = run_member(args, name, depth, pitch, theta)
        p = r["patches"]["patches"]
        print("| %s%s | %.3f | %.2f | %d | %.2e / %.2e = **%.2f** | %.2f / %.2f | %s (%.2f, %.3f) |" % (
            name, " (held back)" if held else "", depth, pitch, theta, r["patches"]["inside"], r["base"]["inside"],
            r["patches"]["inside"] / r["base"]["inside"], r["patches"]["coverage"], r["base"]["coverage"],
            p.get("decision", "?"), p.get("gain", 0.0), p.get("patch_side", 0.0)), flush=True)


if __name__ == "__main__":
    main()
