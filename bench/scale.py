#!/usr/bin/env python3
"""Speed and memory at scale (issue 9): `fill-holes` (self-similar, default settings) and `compress`
on one scan at 25k, 100k, 400k and 1.6M faces (bench/make_scale_cases: lucy decimated, as it is,
subdivided once and twice, 12 holes of radius 0.035), on 1 and 2 threads. Each run is one process:
wall time, peak resident memory (ru_maxrss of that child, from os.wait4) and the tool's own
per-stage seconds (--json). Writes OUT/scale.csv, OUT/scale.md, OUT/scale_time.png and
OUT/scale_memory.png.

usage: scale.py [--tool build/pcl_patchdict] [--cases-tool build/bench/make_scale_cases]
                [--mesh ../shared/data/meshes/lucy.obj] [--out bench/results] [--quick]
--quick: 25k and 100k faces, 2 threads only (CI smoke, about half a minute).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
from line_plot import line_plot  # noqa: E402


def run(command):
    """Runs one preparation step; exits with its stderr on failure."""
    process = subprocess.run([str(c) for c in command], capture_output=True, text=True)
    if process.returncode != 0:
        sys.exit(f"scale.py: {' '.join(map(str, command))} failed:\n{process.stderr}")


def measure(command):
    """Wall seconds, peak RSS (MB) and parsed JSON stdout of one child, via os.wait4."""
    read_end, write_end = os.pipe()
    start = time.monotonic()
    pid = os.fork()
    if pid == 0:
        try:
            os.close(read_end)
            os.dup2(write_end, 1)
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 2)
            os.execvp(str(command[0]), [str(c) for c in command])
        finally:
            os._exit(127)  # exec failed: never fall back into the parent's Python
    os.close(write_end)
    chunks = []
    while True:
        chunk = os.read(read_end, 1 << 16)
        if not chunk:
            break
        chunks.append(chunk)
    os.close(read_end)
    _, status, usage = os.wait4(pid, 0)
    wall = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"scale.py: {' '.join(map(str, command))} failed (exit {os.waitstatus_to_exitcode(status)})")
    return wall, usage.ru_maxrss / 1024.0, json.loads(b"".join(chunks).decode())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tool", default=str(ROOT / "build" / "pcl_patchdict"))
    parser.add_argument("--cases-tool", default=str(ROOT / "build" / "bench" / "make_scale_cases"))
    parser.add_argument("--mesh", default=str(ROOT.parent / "shared" / "data" / "meshes" / "lucy.obj"))
    parser.add_argument("--out", default=str(ROOT / "bench" / "results"))
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--plot-only", action="store_true", help="redraw the plots from OUT/scale.csv")
    args = parser.parse_args()
    out = Path(args.out)
    if args.plot_only:
        rows = [{"pipeline": r["pipeline"], "faces": int(r["faces"]), "threads": int(r["threads"]),
                 "wall": float(r["wall_s"]), "peak_mb": float(r["peak_mb"])} for r in csv.DictReader(open(out / "scale.csv"))]
        plot(out, rows)
        return
    work = out / "scale_work"
    work.mkdir(parents=True, exist_ok=True)
    mesh = Path(args.mesh)
    if not mesh.exists():
        sys.exit(f"scale.py: {mesh} not found (the scans are in ../shared/data/meshes)")
    stem = mesh.stem
    levels = 2 if args.quick else 4
    prefix = f"{stem}_"

    def sizes_present():
        found = {p.stem[len(prefix):] for p in work.glob(f"{prefix}*k.ply")}
        return sorted((s for s in found if s[:-1].isdigit()), key=lambda s: int(s[:-1]))

    if len(sizes_present()) < levels:
        run([args.cases_tool, str(mesh), str(work), "--levels", str(levels)])
    sizes = sizes_present()[:levels]
    threads = [2] if args.quick else [1, 2]

    # One dictionary for every compress run: 100 atoms learned from the smallest size, made again on
    # every run (a cached one could come from older code).
    dictionary = work / "dictionary.pdd"
    run([args.tool, "patches", work / f"{stem}_{sizes[0]}.ply", "-o", work / "train.pds", "--quad-length", "0.05",
         "--quiet"])
    run([args.tool, "learn", work / "train.pds", "-o", dictionary, "--quiet"])

    rows = []
    for size in sizes:
        for t in threads:
            holes = work / f"{stem}_{size}_holes.ply"
            wall, rss, report = measure([args.tool, "fill-holes", holes, "-o", work / "filled.ply", "--threads", t,
                                         "--json"])
            stages = dict(report["seconds"])
            stages.update(report.get("repair_stages", {}))
            rows.append({"pipeline": "fill-holes", "faces": report["input_faces"], "threads": t, "wall": wall,
                         "peak_mb": rss, "surface": report.get("surface", ""), "stages": stages})
            print(f"fill-holes {size:>6} {t} thread(s): {wall:6.2f} s, {rss:7.1f} MB", flush=True)
            intact = work / f"{stem}_{size}.ply"
            wall, rss, report = measure([args.tool, "compress", intact, "--dict", dictionary, "-o", work / "c.pdc",
                                         "--quad-length", "0.05", "--no-eval", "--threads", t, "--json"])
            stages = dict(report["seconds"])
            stages.update(report.get("encode_stages", {}))
            rows.append({"pipeline": "compress", "faces": report["faces"], "threads": t, "wall": wall,
                         "peak_mb": rss, "surface": "", "stages": stages})
            print(f"compress   {size:>6} {t} thread(s): {wall:6.2f} s, {rss:7.1f} MB", flush=True)

    stage_names = []
    for row in rows:
        for name in row["stages"]:
            if name not in stage_names:
                stage_names.append(name)
    with open(out / "scale.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["pipeline", "faces", "threads", "wall_s", "peak_mb", "surface"] + stage_names)
        for row in rows:
            writer.writerow([row["pipeline"], row["faces"], row["threads"], f"{row['wall']:.3f}",
                             f"{row['peak_mb']:.1f}", row["surface"]] +
                            [f"{row['stages'].get(n, 0.0):.3f}" for n in stage_names])

    with open(out / "scale.md", "w") as f:
        f.write(f"Input: `{mesh.name}` at {', '.join(sizes)} faces (`bench/make_scale_cases`); one process per run, "
                "wall clock and peak RSS; stage seconds from `--json`.\n\n")
        f.write("| pipeline | faces | threads | wall s | peak MB | main stages (s) |\n|---|---:|---:|---:|---:|---|\n")
        for row in rows:
            s = row["stages"]
            if row["pipeline"] == "fill-holes":
                detail = (f"Liepa {s.get('base', 0):.2f}, check layout {s.get('check_layout', 0):.2f} + patches "
                          f"{s.get('check_patches', 0):.2f} + prediction {s.get('check_prediction', 0):.2f}, "
                          f"patch stage {s.get('patch_stage', 0) - s.get('surface_check', 0):.2f}, "
                          f"solve {s.get('solve', 0):.2f}, load+write {s.get('load', 0) + s.get('write', 0):.2f}")
            else:
                detail = (f"layout {s.get('layout', 0):.2f}, patches {s.get('patches', 0):.2f}, coding "
                          f"{s.get('coding', 0):.2f}, coverage {s.get('coverage', 0):.2f}, "
                          f"load {s.get('load', 0):.2f}")
            f.write(f"| {row['pipeline']} | {row['faces']:,} | {row['threads']} | {row['wall']:.2f} | "
                    f"{row['peak_mb']:.0f} | {detail} |\n")

    plot(out, rows)


def plot(out, rows):
    """OUT/scale_time.png and OUT/scale_memory.png: log-log against faces; blue fill-holes, red
    compress; dashed 1 thread, solid 2 (line_plot: no matplotlib needed)."""
    for name, key in (("scale_time.png", "wall"), ("scale_memory.png", "peak_mb")):
        series = []
        for pipeline, colour in (("fill-holes", "blue"), ("compress", "red")):
            for t in (1, 2):
                points = [(r["faces"], r[key]) for r in rows if r["pipeline"] == pipeline and r["threads"] == t]
                if points:
                    series.append(([p[0] for p in points], [p[1] for p in points], colour, t == 1))
        line_plot(str(out / name), series, x_log=True, y_log=True)

if __name__ == "__main__":
    main()
