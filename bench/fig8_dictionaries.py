#!/usr/bin/env python3
"""The paper's Fig. 8b and 8c (Sarkar et al. 2017, section 5.4, "shape independence") on the bunny.

8b: reconstruction error of the bunny through a LOCAL dictionary (learned from the bunny's own
    patches, K-SVD) and a GLOBAL one (learned from other shapes' patches, online learning), against
    the number of atoms.
8c: reconstruction error of the bunny through global dictionaries of --atoms-8c atoms learned from
    the patches of the first n training shapes, n = 1 … N (the paper: 500 atoms; it saturates after
    about 6 shapes).
Patches: `patches --grid 16 --quad-length 0.03` (overlap 1) of each shape; learning: `learn`;
error: `reconstruct --dict --sparsity min(20, K) --json`, vertex_to_surface_mean (mean distance of
the reconstructed vertices to the bunny, unit-cube units), as in fig7_atoms.py.
Writes OUT/fig8b_local_global.{csv,png} and OUT/fig8c_shapes.{csv,png}.

usage: bench/fig8_dictionaries.py [--tool build/pcl_patchdict] [--meshes ../shared/data/meshes]
       [--out bench/results] [--atoms 5,10,20,50,100,200,500] [--atoms-8c 200] [--quick]
--quick: atoms 10,50, three small training shapes, 8c at n = 1 and 3 (CI smoke, about a minute).
"""
import argparse
import csv
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from fig7_atoms import run as fig7_run  # noqa: E402
from line_plot import line_plot  # noqa: E402

# Training order for 8c: a fixed, mixed order of the scans other than the bunny.
TRAINING = ["armadillo.obj", "fandisk.obj", "happy_buddha.obj", "max_planck.obj", "chinese_dragon.off",
            "demosthenes.obj", "skull.obj", "boot.obj", "mountain.obj", "lucy.obj"]
QUICK_TRAINING = ["max_planck.obj", "fandisk.obj", "demosthenes.obj"]


def run(tool, *args):
    """fig7_atoms.run, with any argument type."""
    return fig7_run(tool, *[str(a) for a in args])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tool", default=os.path.join(ROOT, "build", "pcl_patchdict"))
    parser.add_argument("--mesh", default=os.path.join(ROOT, "data", "bunny.obj"))
    parser.add_argument("--meshes", default=os.path.join(ROOT, "..", "shared", "data", "meshes"))
    parser.add_argument("--out", default=os.path.join(HERE, "results"))
    parser.add_argument("--atoms", default="5,10,20,50,100,200,500")
    parser.add_argument("--atoms-8c", default="200")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    atoms = [10, 50] if args.quick else [int(a) for a in args.atoms.split(",")]
    training = [t for t in (QUICK_TRAINING if args.quick else TRAINING) if os.path.exists(os.path.join(args.meshes, t))]
    if not training:
        sys.exit("fig8_dictionaries.py: no training shape found in %s" % args.meshes)
    counts = [1, len(training)] if args.quick else list(range(1, len(training) + 1))
    os.makedirs(args.out, exist_ok=True)
    common = ["--threads", "2", "--quiet"]
    with tempfile.TemporaryDirectory() as work:
        own = os.path.join(work, "bunny.pds")
        run(args.tool, "patches", args.mesh, "-o", own, "--grid", "16", "--quad-length", "0.03", *common)
        shape_pds = []
        for name in training:
            pds = os.path.join(work, os.path.splitext(name)[0] + ".pds")
            run(args.tool, "patches", os.path.join(args.meshes, name), "-o", pds, "--grid", "16", "--quad-length",
                "0.03", *common)
            shape_pds.append(pds)
        out = os.path.join(work, "out.ply")

        def error(pdd, k):
            r = run(args.tool, "reconstruct", args.mesh, "-o", out, "--dict", pdd, "--sparsity", str(min(20, k)),
                    "--json", *common)
            return r["vertex_to_surface_mean"]

        rows_b = []
        for k in atoms:
            sparsity = str(min(20, k))
            local = os.path.join(work, "local%d.pdd" % k)
            run(args.tool, "learn", own, "-o", local, "--atoms", k, "--sparsity", sparsity, "--iterations", "10",
                *common)
            glob = os.path.join(work, "global%d.pdd" % k)
            run(args.tool, "learn", *shape_pds, "-o", glob, "--atoms", k, "--sparsity", sparsity, "--method",
                "online", "--iterations", "1" if args.quick else "2", *common)
            rows_b.append([k, error(local, k), error(glob, k)])
            print("8b: %4d atoms: local %.4e, global (%d shapes) %.4e" % (k, rows_b[-1][1], len(training),
                                                                          rows_b[-1][2]), flush=True)
        k = 50 if args.quick else int(args.atoms_8c)
        rows_c = []
        for n in counts:
            glob = os.path.join(work, "shapes%d.pdd" % n)
            run(args.tool, "learn", *shape_pds[:n], "-o", glob, "--atoms", k, "--sparsity", str(min(20, k)),
                "--method", "online", "--iterations", "1" if args.quick else "2", *common)
            rows_c.append([n, training[n - 1], error(glob, k)])
            print("8c: %2d shape(s) (+%s), %d atoms: %.4e" % (n, training[n - 1], k, rows_c[-1][2]), flush=True)

    with open(os.path.join(args.out, "fig8b_local_global.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["atoms", "local_error", "global_error"])
        writer.writerows(rows_b)
    with open(os.path.join(args.out, "fig8c_shapes.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["shapes", "last_added", "global_error", "atoms"])
        writer.writerows([r + [k] for r in rows_c])
    line_plot(os.path.join(args.out, "fig8b_local_global.png"),
              [([r[0] for r in rows_b], [r[1] for r in rows_b], "blue", False),
               ([r[0] for r in rows_b], [r[2] for r in rows_b], "red", False)], x_log=True)
    line_plot(os.path.join(args.out, "fig8c_shapes.png"), [([r[0] for r in rows_c], [r[2] for r in rows_c], "red", False)])
    with open(os.path.join(args.out, "fig8.md"), "w") as f:
        f.write("**Fig. 8b** (bunny, mean vertex-to-surface distance ×1e-3 after the round trip; local: K-SVD on "
                "the bunny's patches; global: online learning on %d other scans):\n\n" % len(training))
        f.write("| atoms | local | global | global / local |\n|---:|---:|---:|---:|\n")
        for k_, l, g in rows_b:
            f.write("| %d | %.4f | %.4f | %.2f |\n" % (k_, 1e3 * l, 1e3 * g, g / l))
        f.write("\n**Fig. 8c** (bunny through global dictionaries of %d atoms learned from the first n scans):\n\n" % k)
        f.write("| n | added | error ×1e-3 |\n|---:|---|---:|\n")
        for n, name, e in rows_c:
            f.write("| %d | %s | %.4f |\n" % (n, name, 1e3 * e))
    print("wrote fig8b_local_global.{csv,png}, fig8c_shapes.{csv,png} and fig8.md in %s" % args.out)


if __name__ == "__main__":
    main()
