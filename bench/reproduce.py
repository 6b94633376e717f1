#!/usr/bin/env python3
"""One command for every experiment of the paper (Sarkar et al. 2017, 3DV) and our comparisons.

Runs, in order, writing into OUT (default bench/results/) and assembling OUT/RESULTS.md:
  fig7     Fig. 7: round-trip error against dictionary atoms (local, bunny)    fig7_atoms.py
  table1   Table 1 and a rate-distortion curve beside Draco                    codec_rate_distortion.py
  repair   Table 2 (missing vertices: harmonic, bi-Laplacian, patches self-similar / global / local),
           Tables 3–4 (holes: Liepa alone vs self-similar / global / local), denoising vs Laplacian
           and Taubin at their oracle iteration counts                         build/bench/repair_tables
  fig8a    Fig. 8a: hole-fill error against hole size / patch size             build/bench/hole_size_sweep
  fig8bc   Fig. 8b (local vs global against atoms), 8c (global vs number of shapes)  fig8_dictionaries.py
  scale    fill-holes and compress at 25k–1.6M faces, 1 and 2 threads: time per stage, peak memory
                                                                               scale.py
  real     fill-holes and denoise on real Kinect scans and a LiDAR tile: punched holes against harmonic
           image/grid fills, whole scans, plane roughness against PCL's MLS   real_scans.py
  spinning the same on spinning-LiDAR frames (Ouster) against a harmonic range-image fill, and the
           frame rate                                                          spinning_scans.py
Meshes: data/bunny.obj (bundled) and ../shared/data/{meshes,textured} (the project's sibling folder).
The global dictionary of the repair tables is learned from scans the tables do not repair.

usage: bench/reproduce.py [--quick] [--only STEP,...] [--build build] [--out bench/results]
--quick: every step on small inputs (CI smoke, about 2 min on 2 cores); the full run takes about
15 min on 2 idle cores (820 s measured). Needs a Release build with the bench programs (scripts/build.sh does it).
"""
import argparse
import csv
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from line_plot import line_plot  # noqa: E402

STEPS = ["fig7", "table1", "repair", "fig8a", "fig8bc", "scale", "real", "spinning"]
REPAIR_MESHES = ["boot.obj", "demosthenes.obj", "max_planck.obj", "lucy.obj", "bunny.obj", "fandisk.obj"]
GLOBAL_TRAINING = ["armadillo.obj", "chinese_dragon.off", "happy_buddha.obj", "mountain.obj", "skull.obj"]
SWEEP_MESHES = ["textured/sole.ply", "textured/knurl.ply", "textured/tiles.ply", "meshes/boot.obj",
                "meshes/demosthenes.obj"]


def run(command, log, capture=None):
    """Runs a step's command, its output appended to the log (stdout to `capture` if given)."""
    command = [str(c) for c in command]
    with open(log, "a") as f:
        f.write("$ " + " ".join(command) + "\n")
        f.flush()
        stdout = open(capture, "w") if capture else f
        result = subprocess.run(command, stdout=stdout, stderr=f)
        if capture:
            stdout.close()
    if result.returncode != 0:
        sys.exit("reproduce.py: step failed (exit %d): %s — see %s" % (result.returncode, " ".join(command), log))


def git_commit():
    try:
        commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip()
        return commit + (" (with uncommitted changes)" if dirty else "")
    except OSError:
        return "unknown"


def fig7(a, out, log):
    extra = ["--atoms", "10,50", "--iterations", "3"] if a.quick else []
    run([sys.executable, HERE / "fig7_atoms.py", "--tool", a.tool, "--out", out / "fig7_atoms", *extra], log)
    rows = list(csv.DictReader(open(out / "fig7_atoms.csv")))
    md = ["| atoms | mean vertex-to-surface ×1e-3 | vertex RMSE ×1e-3 | PSNR dB |", "|---:|---:|---:|---:|"]
    for r in rows:
        md.append("| %s | %.4f | %.4f | %.2f |" % ("identity" if r["atoms"] == "0" else r["atoms"],
                                                  1e3 * float(r["vertex_to_surface_mean"]),
                                                  1e3 * float(r["vertex_rmse"]), float(r["psnr_db"])))
    return ("Fig. 7 — round trip of the bunny through local dictionaries (16×16 patches, L 0.03, "
            "≤ 20 non-zeros)", "\n".join(md), ["fig7_atoms.png"])


def table1(a, out, log):
    run([sys.executable, HERE / "codec_rate_distortion.py", "--tool", a.tool, "--meshes", a.shared / "meshes",
         "--out", out / "codec_rd", *(["--quick"] if a.quick else [])], log)
    return ("Table 1 — compression with a global dictionary (100 atoms), beside Draco",
            open(out / "codec_rd_table1.md").read().strip(), ["codec_rd.png"])


def global_dictionary(a, out, log):
    """100 atoms (K-SVD, 20 iterations) from 16×16 patches of side 0.058 of scans the repair tables do not use."""
    work = out / "repair_work"
    work.mkdir(exist_ok=True)
    training = GLOBAL_TRAINING[:2] if a.quick else GLOBAL_TRAINING
    pdd = work / ("global_%d.pdd" % len(training))
    sets = []  # made again on every run: a cached dictionary could come from older code
    for name in training:
        pds = work / (Path(name).stem + ".pds")
        run([a.tool, "patches", a.shared / "meshes" / name, "-o", pds, "--quad-length", "0.058", "--quiet"], log)
        sets.append(pds)
    run([a.tool, "learn", *sets, "-o", pdd, "--method", "ksvd", "--quiet"], log)
    return pdd, training


def repair(a, out, log):
    meshes = ["max_planck.obj"] if a.quick else REPAIR_MESHES
    paths = [ROOT / "data" / "bunny.obj" if m == "bunny.obj" else a.shared / "meshes" / m for m in meshes]
    pdd, training = global_dictionary(a, out, log)
    run([a.build / "bench" / "repair_tables", *paths, "--dict", pdd, "--local", "--csv", out / "repair_tables.csv"],
        log, capture=out / "repair_tables.md")
    note = ("Cases of `bench/repair_tables` (seeded damage of `mesh_damage.h` on the evaluation protocol of docs/design.md, not the "
            "harness's draw); global dictionary: 100 atoms from patches of side 0.058 of %s; local: learned from "
            "the clean mesh at the patch side the repair used. The bundled bunny keeps its five base openings, "
            "which `fill-holes` also closes: its new→GT includes them.\n\n" % ", ".join(training))
    return ("Tables 2, 3–4 and denoising — repairs against the classic baselines",
            note + open(out / "repair_tables.md").read().strip(), [])


def fig8a(a, out, log):
    # The paper's protocol: one patch side (0.062) for every hole size, so that x = hole diameter /
    # patch side; quads of that length, the patch side = 1 × L (hole_size_sweep --quad-length).
    meshes = ["meshes/max_planck.obj"] if a.quick else SWEEP_MESHES
    radii = ["--radii", "0.02,0.035"] if a.quick else []
    run([a.build / "bench" / "hole_size_sweep", *[a.shared / m for m in meshes], *radii, "--quad-length", "0.062"],
        log, capture=out / "fig8a_hole_size.csv")
    rows = list(csv.DictReader(open(out / "fig8a_hole_size.csv")))
    colours = ["blue", "red", "green", "orange", "purple", "grey"]
    series = []
    names = list(dict.fromkeys(r["mesh"] for r in rows))
    for i, name in enumerate(names):
        mine = [r for r in rows if r["mesh"] == name]
        xs = [float(r["diameter_over_side"]) for r in mine]
        series.append((xs, [1e3 * float(r["patch_removed"]) for r in mine], colours[i % len(colours)], False))
        series.append((xs, [1e3 * float(r["liepa_removed"]) for r in mine], colours[i % len(colours)], True))
    line_plot(str(out / "fig8a_hole_size.png"), series)
    md = ["| mesh | radius | hole d / patch side | relief | Liepa removed→out ×1e-3 | patches | Liepa − patches "
          "| patches / Liepa |",
          "|---|---:|---:|---|---:|---:|---:|---:|"]
    for r in rows:
        liepa, patches = 1e3 * float(r["liepa_removed"]), 1e3 * float(r["patch_removed"])
        md.append("| %s | %s | %.2f | %s | %.3f | %.3f | %.3f | %.2f |" % (
            r["mesh"], r["radius"], float(r["diameter_over_side"]), "yes" if r["relief"] == "1" else "no",
            liepa, patches, liepa - patches, float(r["ratio_removed"])))
    caption = ("Patch side fixed at 0.062 (the paper's), 6 seeded holes per radius. Plot: removed→out error ×1e-3 "
               "(y) against hole diameter / patch side (x); solid = patches, dashed = Liepa; per mesh "
               + ", ".join("%s %s" % (colours[i % len(colours)], n) for i, n in enumerate(names)) + ".")
    return ("Fig. 8a — hole-fill error against hole size", "\n".join(md) + "\n\n" + caption, ["fig8a_hole_size.png"])


def fig8bc(a, out, log):
    run([sys.executable, HERE / "fig8_dictionaries.py", "--tool", a.tool, "--meshes", a.shared / "meshes", "--out",
         out, *(["--quick"] if a.quick else [])], log)
    return ("Fig. 8b, 8c — local against global dictionaries",
            open(out / "fig8.md").read().strip() + "\n\nPlots: 8b blue local, red global (x: atoms, log); "
            "8c: error against the number of shapes.", ["fig8b_local_global.png", "fig8c_shapes.png"])


def scale(a, out, log):
    run([sys.executable, HERE / "scale.py", "--tool", a.tool, "--cases-tool", a.build / "bench" / "make_scale_cases",
         "--mesh", a.shared / "meshes" / "lucy.obj", "--out", out, *(["--quick"] if a.quick else [])], log)
    return ("Speed and memory at scale", open(out / "scale.md").read().strip() +
            "\n\nPlots: wall seconds, then peak MB, against faces (log-log); blue fill-holes, red compress; dashed "
            "1 thread, solid 2.", ["scale_time.png", "scale_memory.png"])


def real_scan_step(a, out, log, name, title, script, *arguments):
    """A step over ../shared/data/real (skipped when absent): `script` writes OUT/name/name.md, whose
    body (without its title) is the step's section."""
    if not (a.shared / "real").is_dir():
        print("reproduce.py: %s skipped: %s not found" % (name, a.shared / "real"), flush=True)
        return title, "*Skipped: %s not found.*" % (a.shared / "real"), []
    # numpy and scipy come from Debian (install-deps.sh --bench): its interpreter, not another on PATH.
    python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
    run([python, HERE / script, "--tool", a.tool, *arguments, "--out", out / name,
         *(["--quick"] if a.quick else [])], log)
    body = open(out / name / (name + ".md")).read().strip().split("\n", 1)[1]
    return title, body.strip(), []


def real(a, out, log):
    return real_scan_step(a, out, log, "real_scans", "Real sensor scans — Kinect frames and an airborne LiDAR tile",
                          "real_scans.py", "--shared", a.shared)


def spinning(a, out, log):
    return real_scan_step(a, out, log, "spinning_scans", "Spinning LiDAR frames — Ouster OS1-32, OS2-32, OS1-128",
                          "spinning_scans.py", "--frames-dir", a.shared / "real")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--only", default=",".join(STEPS), help="comma-separated steps: " + ", ".join(STEPS))
    parser.add_argument("--build", default=str(ROOT / "build"))
    parser.add_argument("--out", default=str(HERE / "results"))
    parser.add_argument("--shared", default=str(ROOT.parent / "shared" / "data"))
    a = parser.parse_args()
    a.build, a.shared = Path(a.build).resolve(), Path(a.shared).resolve()
    a.tool = a.build / "pcl_patchdict"
    out = Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    steps = [s for s in a.only.split(",") if s]
    unknown = [s for s in steps if s not in STEPS]
    if unknown:
        sys.exit("reproduce.py: unknown step(s) %s (steps: %s)" % (", ".join(unknown), ", ".join(STEPS)))
    missing = [p for p in (a.tool, *(a.build / "bench" / b for b in ("repair_tables", "hole_size_sweep",
                                                                         "make_scale_cases"))) if not p.exists()]
    if missing:
        sys.exit("reproduce.py: %s not built — run scripts/build.sh first" % ", ".join(map(str, missing)))
    if not (a.shared / "meshes").is_dir():
        sys.exit("reproduce.py: %s not found — the scans live in ../shared/data beside the project" % a.shared)
    log = out / "reproduce.log"
    with open(log, "a") as f:
        f.write("# reproduce.py %s\n" % " ".join(sys.argv[1:]))
    commit = git_commit()  # at the start: the code the results come from
    mode = " --quick" if a.quick else ""
    for step in steps:
        start = time.monotonic()
        print("reproduce.py: %s …" % step, flush=True)
        title, body, figures = globals()[step](a, out, log)
        seconds = time.monotonic() - start
        # Each step keeps its own section, so that a partial rerun (--only) updates just its part.
        section = ["## " + title, "", "*(`reproduce.py%s`, commit %s, %s UTC, %.0f s)*" % (
            mode, commit, time.strftime("%Y-%m-%d %H:%M", time.gmtime()), seconds), "", body, ""]
        section += ["![%s](%s)" % (f, f) for f in figures]
        (out / ("section_%s.md" % step)).write_text("\n".join(section) + "\n")
        print("reproduce.py: %s done in %.0f s" % (step, seconds), flush=True)
    lines = ["# Results of `bench/reproduce.py`", "",
             "%s, %d cores. Each section names the commit and the mode it was made with; regenerate with "
             "`python3 bench/reproduce.py [--quick] [--only STEP,...]` after `scripts/build.sh`. Errors are in "
             "unit-cube units (largest bounding-box side 1)." % (platform.platform(terse=True), os.cpu_count() or 0),
             ""]
    for step in STEPS:
        path = out / ("section_%s.md" % step)
        if path.exists():
            lines.append(path.read_text())
    (out / "RESULTS.md").write_text("\n".join(lines))
    print("reproduce.py: wrote %s" % (out / "RESULTS.md"))


if __name__ == "__main__":
    main()
