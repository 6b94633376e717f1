#!/usr/bin/python3
"""Same outputs before and after a refactor: builds two revisions (clean Release builds, timed), runs the same
commands with both tools and compares every output file byte for byte.

usage: /usr/bin/python3 bench/same_outputs.py --base REV [--head REV] [--work DIR] [--jobs 2] [--threads 2]
           [--reuse] [--keep] [--quick] [--only REGEX] [--data DIR] [--harness DIR]
       /usr/bin/python3 bench/same_outputs.py --self-check      (the comparison on made-up folders; no build)

1. REV and --head (default HEAD; both resolved to commits at the start) are checked out with
   `git worktree add --detach` under --work (default /tmp/same_outputs: base/, head/; two runs at once need
   two --work folders) and built as scripts/build.sh does (`cmake -DCMAKE_BUILD_TYPE=Release`, `cmake --build
   -j JOBS`: everything, tests, benches and examples too; install-deps.sh is not run). The wall and CPU
   seconds of each clean build (configure + build) are printed, with the load average at its start: compare
   wall times only on an idle machine. --reuse keeps a worktree at the right commit whose build exists
   (from an earlier --keep run).
2. The STEPS below run with both tools (OMP_NUM_THREADS=--threads for both), each in its own empty folder
   (--work/out/{base,head}/<step>/, the --json report and stderr beside it). Every file is compared by sha256,
   and the --json report after dropping timing keys (seconds*, *_stages, threads, wall, time, rss, memory)
   and writing the worktree and output paths as {SRC} and {OUT}. When the two differ, the base runs again (up
   to 3 times, <step>~again/): what varies between runs of one binary is the run, not the revision. One line a step:
   same; same* (files equal, a report value varies run to run); DIFFERENT (the first differing file or
   report key); UNSTABLE (an output file varies run to run); FAILED (an exit code). Exit status 1 unless
   every step is same or same*.
3. The worktrees are removed at the end, also on failure, unless --keep; the outputs too unless --keep or
   a step was not the same.

Cases: the project's own damage (make_test_inputs, repair_tables --write-cases, 20 % of bunny's vertices picked
here) and, when --harness is there, its cases.py, cases_extra.py and real_clouds.py cases (made once, in
--work/inputs); the codec's Table 1 files; the demo. The STEPS table lists them all; --quick runs those flagged q
(about 2 min on 2 idle cores for both tools; the full run about 8 min).
"""
import argparse
import hashlib
import json
import os
import random
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TIMING_KEY = re.compile(r"(^|_)(seconds|time|wall|threads?|rss|memory)($|_)|_stages$")
TRAINING = ["chinese_dragon.off", "happy_buddha.obj", "mountain.obj", "skull.obj", "boot.obj", "demosthenes.obj"]
TABLE1 = [("bunny", "0.07", "0.08"), ("fandisk", "0.05", "0.08"), ("armadillo", "0.064", "0.08"),
          ("lucy", "0.045", "0.08"), ("max_planck", "0.12", "0.02")]


def git(*args):
    result = subprocess.run(["git", "-C", ROOT] + list(args), capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError("git %s: %s" % (" ".join(args), result.stderr.strip()))
    return result.stdout.strip()


# ---------------------------------------------------------------- builds

def prepare(label, rev, commit, args, created):
    """Worktree of commit at WORK/label, built clean (Release); returns (dict, (wall, CPU seconds) or None)."""
    path = os.path.join(args.work, label)
    build = os.path.join(path, "build")
    side = dict(label=label, rev=rev, commit=commit, src=path, build=build)
    created.append(path)
    checked_out = subprocess.run(["git", "-C", path, "rev-parse", "HEAD"], capture_output=True, text=True).stdout
    if args.reuse and checked_out.strip() == commit and os.path.isfile(os.path.join(build, "pcl_patchdict")):
        return side, None
    cleanup([path], prune=False)
    git("worktree", "add", "--detach", path, commit)
    log = os.path.join(args.work, "build-%s.log" % label)
    print("building %s (%s %s) in %s, load %.2f ..." % (label, rev, commit[:9], build, os.getloadavg()[0]), flush=True)
    start, cpu = time.monotonic(), children_cpu()
    with open(log, "w") as out:
        for command in (["cmake", "-S", path, "-B", build, "-DCMAKE_BUILD_TYPE=Release"],
                        ["cmake", "--build", build, "-j", str(args.jobs)]):
            if subprocess.run(command, stdout=out, stderr=subprocess.STDOUT).returncode != 0:
                raise RuntimeError("build of %s failed: see %s" % (label, log))
    seconds = (time.monotonic() - start, children_cpu() - cpu)
    print("  %s: clean Release build %.0f s wall, %.0f s CPU (-j %d)" % ((label,) + seconds + (args.jobs,)), flush=True)
    return side, seconds


def children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)  # of the compilers too: make waits for them
    return usage.ru_utime + usage.ru_stime


def cleanup(paths, prune=True):
    for path in paths:
        subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", path], capture_output=True)
        shutil.rmtree(path, ignore_errors=True)
    if prune:
        subprocess.run(["git", "-C", ROOT, "worktree", "prune"], capture_output=True)


def find_binary(build, relative):
    """build/relative, or the first executable of that name anywhere in the build (a refactor may move it)."""
    path = os.path.join(build, relative)
    if os.access(path, os.X_OK):
        return path
    name = os.path.basename(relative)
    for folder, _, files in os.walk(build):
        if name in files and os.access(os.path.join(folder, name), os.X_OK):
            return os.path.join(folder, name)
    return path


# ---------------------------------------------------------------- inputs made here (the same for both sides)

def make_inputs(args):
    """WORK/inputs: a missing-vertex list for bunny; the harness's cases when it is there. (inputs, harness?)"""
    inputs, data = os.path.join(args.work, "inputs"), args.data
    os.makedirs(inputs, exist_ok=True)
    with open(os.path.join(data, "meshes", "bunny.obj")) as f:
        count = sum(1 for line in f if line.startswith("v "))
    with open(os.path.join(inputs, "bunny_missing.txt"), "w") as f:
        f.write("".join("%d\n" % v for v in sorted(random.Random(7).sample(range(count), count // 5))))
    harness = os.path.isfile(os.path.join(args.harness, "cases.py"))
    py, cases = "/usr/bin/python3", os.path.join(inputs, "harness")  # Debian's, with numpy and scipy
    runs = [["cases.py", data + "/meshes/bunny.obj"] + ([] if args.quick else [data + "/textured/sole.ply"])
            + ["--out", cases]] + ([] if args.quick else [["cases_extra.py", cases + "/bunny"]])
    if os.path.isdir(os.path.join(data, "real")):
        runs += [["real_clouds.py", "make", "%s/real/%s.pcd" % (data, scan), os.path.join(cases, scan), "--holes",
                  "8", "--seed", "1"] + extra for scan, extra in (("mosd_learn0", []),
                                                                  ("terrain_csite3", ["--radius-m", "8,25"]))]
    for command in runs if harness else []:
        if subprocess.run([py, os.path.join(args.harness, command[0])] + command[1:], capture_output=True).returncode:
            raise RuntimeError("harness case generation failed: " + " ".join(command))
    print("inputs in %s (harness cases: %s)" % (inputs, "yes" if harness else "no, %s absent" % args.harness))
    return inputs, harness


# ---------------------------------------------------------------- the commands

# FLAGS NAME COMMAND (a line starting with spaces continues the one above). FLAGS: q in --quick, h needs the
# harness cases, r needs ../shared/data/real, - none. COMMAND: `tool` is pcl_patchdict (--json added), `bin:PATH` a
# program of the build; @STEP/FILE is that step's output on the same side; {m} {t} {r} the data's meshes/,
# textured/, real/; {in} WORK/inputs, {h} its harness cases ({hb}, {hs}: bunny's, sole's); {dict} the small dictionary.
STEPS = """
q  holes_bunny              bin:examples/make_test_inputs holes {m}/bunny.obj holes.ply
-  holes_sole               bin:examples/make_test_inputs holes {t}/sole.ply holes.ply
q  cloud_bunny              bin:examples/make_test_inputs cloud {m}/bunny.obj cloud.pcd
-  cases_fandisk            bin:bench/repair_tables {m}/fandisk.obj --write-cases . --seed 1
q  learn_small              tool learn {m}/boot.obj -o small.pdd --atoms 50 --sparsity 8 --seed 1
q  fill_bunny_liepa         tool fill-holes @holes_bunny/holes.ply -o out.ply --no-patches
-  fill_bunny_self          tool fill-holes @holes_bunny/holes.ply -o out.ply
q  fill_bunny_dict          tool fill-holes @holes_bunny/holes.ply -o out.ply {dict}
-  fill_sole_dict           tool fill-holes @holes_sole/holes.ply -o out.ply {dict}
-  fill_fandisk_report      tool fill-holes @cases_fandisk/fandisk_holes.ply -o out.ply --report report
                                --ref @cases_fandisk/fandisk_truth.ply
-  inpaint_bunny_liepa      tool inpaint {m}/bunny.obj --missing {in}/bunny_missing.txt -o out.ply --no-patches
-  inpaint_bunny_self       tool inpaint {m}/bunny.obj --missing {in}/bunny_missing.txt -o out.ply
-  inpaint_bunny_dict       tool inpaint {m}/bunny.obj --missing {in}/bunny_missing.txt -o out.ply {dict}
-  denoise_fandisk_taubin   tool denoise @cases_fandisk/fandisk_noisy.ply -o out.ply --no-patches
-  denoise_fandisk_self     tool denoise @cases_fandisk/fandisk_noisy.ply -o out.ply --self-similar
-  denoise_fandisk_dict     tool denoise @cases_fandisk/fandisk_noisy.ply -o out.ply {dict}
q  denoise_cloud_bunny      tool denoise @cloud_bunny/cloud.pcd -o out.pcd
-  fill_denoise_cloud_bunny tool fill-holes @cloud_bunny/cloud.pcd --denoise -o out.pcd
qh h_inpaint_bunny_liepa    tool inpaint {hb}/missing_0.2.ply --missing {hb}/missing_0.2.txt -o out.ply --no-patches
h  h_inpaint_bunny_self     tool inpaint {hb}/missing_0.2.ply --missing {hb}/missing_0.2.txt -o out.ply
qh h_inpaint_bunny_dict     tool inpaint {hb}/missing_0.2.ply --missing {hb}/missing_0.2.txt -o out.ply {dict}
qh h_fill_bunny_liepa       tool fill-holes {hb}/holes_0.035.ply -o out.ply --no-patches
h  h_fill_bunny_self        tool fill-holes {hb}/holes_0.035.ply -o out.ply
qh h_fill_bunny_dict        tool fill-holes {hb}/holes_0.035.ply -o out.ply {dict}
qh h_denoise_bunny_taubin   tool denoise {hb}/noise_0.5.ply -o out.ply --no-patches
h  h_denoise_bunny_self     tool denoise {hb}/noise_0.5.ply -o out.ply --self-similar
h  h_denoise_bunny_dict     tool denoise {hb}/noise_0.5.ply -o out.ply {dict}
h  h_fill_sole_self         tool fill-holes {hs}/holes_0.02.ply -o out.ply
h  h_inpaint_sole_dict      tool inpaint {hs}/missing_0.2.ply --missing {hs}/missing_0.2.txt -o out.ply {dict}
h  h_denoise_cloud_bunny    tool denoise {hb}/cloud_noise_0.5.ply -o out.ply
h  h_fill_cloud_bunny       tool fill-holes {hb}/cloud_holes.ply -o out.ply
qh h_fill_mosd_learn0       tool fill-holes {h}/mosd_learn0/holed.pcd -o out.pcd
qh h_fill_terrain_csite3    tool fill-holes {h}/terrain_csite3/holed.pcd -o out.pcd
qr fill_kinect_frame        tool fill-holes {r}/kinect_frame_142256.pcd -o out.pcd
qr denoise_kinect_frame     tool denoise {r}/kinect_frame_142256.pcd -o out.pcd
qr fill_denoise_kinect_frame tool fill-holes {r}/kinect_frame_142256.pcd --denoise -o out.pcd
r  fill_mosd_learn0         tool fill-holes {r}/mosd_learn0.pcd -o out.pcd
r  denoise_mosd_learn0      tool denoise {r}/mosd_learn0.pcd -o out.pcd
r  fill_denoise_mosd_learn0 tool fill-holes {r}/mosd_learn0.pcd --denoise -o out.pcd
qr fill_terrain_csite3      tool fill-holes {r}/terrain_csite3.pcd -o out.pcd
{codec}
q  quads                    tool quads {m}/bunny.obj -o quads.obj --frames frames.ply --coarse coarse.ply
q  patches                  tool patches {m}/bunny.obj -o p.pds --png sheet.png
-  learn_online             tool learn @patches/p.pds @codec_patches_boot/train.pds -o online.pdd --method online
                                --atoms 40 --seed 3 --png atoms.png
-  learn_ksvd_png           tool learn @patches/p.pds -o k.pdd --atoms 40 --sparsity 6 --seed 3 --png atoms.png
-  reconstruct              tool reconstruct {m}/bunny.obj -o out.ply
-  reconstruct_dict         tool reconstruct {m}/bunny.obj -o out.ply {dict}
q  info                     tool info @holes_bunny/holes.ply
q  eval                     tool eval {m}/bunny.obj @fill_bunny_dict/out.ply
-  demo                     tool demo --out demo
"""


def codec_lines(quick):
    """Table 1 of codec_rate_distortion.py: its global dictionary, then each mesh at its Table 1 setting
    (docs/codec_table1.md) and back; --quick: its --quick dictionary (boot, demosthenes) and fandisk."""
    training = ["boot.obj", "demosthenes.obj"] if quick else TRAINING
    lines = ["q codec_patches_%s tool patches {m}/%s -o train.pds --quad-length 0.08 --grid 16"
             % (os.path.splitext(n)[0], n) for n in training]
    lines.append("q codec_learn tool learn %s -o global.pdd --method ksvd --atoms 100 --sparsity 10" % " ".join(
        "@codec_patches_%s/train.pds" % os.path.splitext(n)[0] for n in training))
    for mesh, length, cost in [TABLE1[1]] if quick else TABLE1:
        lines.append("q compress_%s tool compress {m}/%s.obj --dict @codec_learn/global.pdd -o m.pdc --quad-length %s "
                     "--atom-cost %s" % (mesh, mesh, length, cost))
        lines.append("q decompress_%s tool decompress @compress_%s/m.pdc --dict @codec_learn/global.pdd "
                     "-o decoded.ply" % (mesh, mesh))
    return "\n".join(lines)


def steps(args, inputs, harness):
    """[(name, argv)] of this run, from STEPS."""
    text = re.sub(r"\n {20,}", " ", STEPS).replace("{codec}", codec_lines(args.quick))  # continuation lines
    text = text.replace("{dict}", "--dict @learn_small/small.pdd")
    for key, value in (("{hb}", "{h}/bunny"), ("{hs}", "{h}/sole"), ("{m}", args.data + "/meshes"),
                       ("{t}", args.data + "/textured"), ("{r}", args.data + "/real"), ("{h}", inputs + "/harness"),
                       ("{in}", inputs)):
        text = text.replace(key, value)
    real = os.path.isdir(args.data + "/real")
    result = []
    for line in text.strip().splitlines():  # paths without spaces
        flags, name, *argv = line.split()
        if not ((args.quick and "q" not in flags) or ("h" in flags and not harness) or ("r" in flags and not real)):
            result.append((name, argv))
    return result


# ---------------------------------------------------------------- running and comparing

def run_step(side, argv, out_root, folder, env):
    """Runs one command in its empty folder (stdout, the --json report, and stderr beside it)."""
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    tool = argv[0] == "tool"
    command = [os.path.join(side["build"], "pcl_patchdict") if tool else find_binary(side["build"], argv[0][4:])]
    command += [os.path.join(out_root, a[1:]) if a.startswith("@") else a for a in argv[1:]]
    command += ["--json"] if tool else []
    start = time.monotonic()
    with open(folder + ".stdout", "w") as out, open(folder + ".stderr", "w") as err:
        try:
            # The bundled data of the side's own worktree (demo), written {SRC}/data in the report even when
            # the build was made in another folder.
            side_env = dict(env, PCL_PATCHDICT_DATA=os.path.join(side["src"], "data"))
            rc = subprocess.run(command, cwd=folder, env=side_env, stdout=out, stderr=err, timeout=900).returncode
        except (OSError, subprocess.TimeoutExpired) as e:
            err.write("%s\n" % e)
            rc = -1
    return rc, time.monotonic() - start


def flat(value, where=""):
    """{'/key/0/key': leaf} of a parsed report, without the timing keys."""
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else None
    if not items:
        return {where or "/": value}
    result = {}
    for key, item in items:
        if not (isinstance(key, str) and TIMING_KEY.search(key)):
            result.update(flat(item, "%s/%s" % (where, key)))
    return result


def normalised_report(path, replacements):
    """The flattened --json report without timing keys, paths written as placeholders."""
    with open(path) as f:
        text = f.read()
    for old, new in replacements:
        text = text.replace(old, new)
    try:
        return flat(json.loads(text))
    except ValueError:
        return {"/": text}


def json_differences(a, b):
    """{path: 'a != b'} for every difference of two flattened reports."""
    return {k: "%.60r != %.60r" % (a.get(k, "(none)"), b.get(k, "(none)"))
            for k in sorted(set(a) | set(b)) if k not in a or k not in b or a[k] != b[k]}


def digests(folder):
    result = {}
    for directory, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(directory, name)
            with open(path, "rb") as f:
                result[os.path.relpath(path, folder)] = hashlib.sha256(f.read()).hexdigest()
    return result


def compare(folder_a, folder_b, reports=None):
    """(first file that differs or is on one side only, or None; {report path: difference}).
    reports: ((report_a, replacements_a), (report_b, replacements_b)) for the tool's --json reports."""
    a, b = digests(folder_a), digests(folder_b)
    files = next(("%s%s" % (n, "" if n in a and n in b else " only in " + ("head" if n not in a else "base"))
                  for n in sorted(set(a) | set(b)) if a.get(n) != b.get(n)), None)
    return files, json_differences(*(normalised_report(*r) for r in reports)) if reports else {}


def verdict(files, report, files_again, report_again):
    """Base against head, given base against a second base run (what varies run to run is no difference)."""
    if files:
        return ("UNSTABLE", "varies run to run: " + files_again) if files_again else ("DIFFERENT", files)
    real = {k: v for k, v in report.items() if k not in report_again}
    if real:
        return "DIFFERENT", "report %s: %s" % next(iter(real.items()))
    if report:
        return "same*", "report %s varies run to run" % ", ".join(sorted(report))
    return "same", ""


def reports_of(argv, pairs):
    """compare()'s reports for [(folder, root, side)]; None for a build program (its stdout has timings)."""
    if argv[0] != "tool":
        return None
    return [(f + ".stdout", [(f, "{OUT}"), (root, "{OUT}"), (side["src"], "{SRC}")]) for f, root, side in pairs]


def judge(sides, roots, name, argv, env):
    """Runs one step on both sides: (status, detail, [(exit code, seconds)] of base and head)."""
    folders = [os.path.join(root, name) for root in roots]
    results = [run_step(side, argv, root, folder, env) for side, root, folder in zip(sides, roots, folders)]
    if any(rc != 0 for rc, _ in results):
        return "FAILED", "exit %d/%d; see %s.stderr" % (results[0][0], results[1][0], folders[0]), results
    pairs = list(zip(folders, roots, sides))
    files, report = compare(*folders, reports_of(argv, pairs))
    files_again, report_again = None, {}
    for _ in range(3 if files or report else 0):  # the base again: is it the revision or the run?
        folder = folders[0] + "~again"
        run_step(sides[0], argv, roots[0], folder, env)
        found = compare(folders[0], folder, reports_of(argv, [pairs[0], (folder, roots[0], sides[0])]))
        files_again, report_again = files_again or found[0], dict(report_again, **found[1])
        if files or set(report) <= set(report_again):
            break
    return verdict(files, report, files_again, report_again) + (results,)


def run_all(sides, step_list, args):
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
    roots = [os.path.join(args.work, "out", side["label"]) for side in sides]
    for root in roots:
        if not args.only:  # --only keeps the other steps' outputs, for the steps that read them
            shutil.rmtree(root, ignore_errors=True)
        os.makedirs(root, exist_ok=True)
    bad, noisy = [], []
    print("\n%-32s %-9s %7s %7s  %s" % ("step", "result", "base s", "head s", "first difference"))
    for name, argv in step_list:
        status, detail, results = judge(sides, roots, name, argv, env)
        if status == "same*":
            noisy.append(name)
        elif status != "same":
            bad.append(name)
        print("%-32s %-9s %7.1f %7.1f  %s" % (name, status, results[0][1], results[1][1], detail), flush=True)
    return bad, noisy


def self_check():
    """The comparison on made-up folders: equal up to timing keys, then one flipped byte, then one JSON value."""
    with tempfile.TemporaryDirectory() as tmp:
        a, b = os.path.join(tmp, "a"), os.path.join(tmp, "b")
        for folder, seconds in ((a, 1.5), (b, 2.5)):
            os.makedirs(os.path.join(folder, "sub"))
            with open(os.path.join(folder, "sub", "out.ply"), "wb") as f:
                f.write(bytes(range(256)) * 10)
            with open(folder + ".stdout", "w") as f:
                json.dump({"output": folder + "/out.ply", "rmse": 0.25, "seconds": {"load": seconds},
                           "repair_stages": {"base": seconds}, "threads": int(seconds)}, f)
        reports = [(a + ".stdout", [(a, "{OUT}")]), (b + ".stdout", [(b, "{OUT}")])]
        results = [("timing keys and paths ignored", compare(a, b, reports), (None, {}))]
        with open(os.path.join(b, "sub", "out.ply"), "r+b") as f:
            f.seek(1000)
            f.write(b"\xff")
        results.append(("a flipped byte found", compare(a, b, reports), ("sub/out.ply", {})))
        shutil.copy(os.path.join(a, "sub", "out.ply"), os.path.join(b, "sub", "out.ply"))
        os.remove(os.path.join(a, "sub", "out.ply"))
        with open(b + ".stdout", "w") as f:
            json.dump({"output": b + "/out.ply", "rmse": 0.26, "seconds": {"load": 9}}, f)
        results.append(("a missing file, a changed value", compare(a, b, reports),
                        ("sub/out.ply only in head", {"/rmse": "0.25 != 0.26"})))
    results += [("run-to-run noise not counted", verdict(None, {"/x": "1 != 2"}, None, {"/x": "1 != 3"}),
                 ("same*", "report /x varies run to run")),
                ("unstable output reported", verdict("f.ply", {}, "f.ply", {}),
                 ("UNSTABLE", "varies run to run: f.ply"))]
    ok = all(got == expected for _, got, expected in results)
    for what, got, expected in results:
        print("%-34s %s %r" % (what, "ok" if got == expected else "WRONG, expected %r, got" % (expected,), got))
    return 0 if ok else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--base", help="the revision before (any git revision)")
    parser.add_argument("--head", default="HEAD", help="the revision after (default HEAD)")
    parser.add_argument("--work", default="/tmp/same_outputs")
    parser.add_argument("--jobs", type=int, default=2, help="build jobs (cmake --build -j)")
    parser.add_argument("--threads", type=int, default=2, help="OMP_NUM_THREADS of both tools")
    parser.add_argument("--reuse", action="store_true", help="keep a worktree's existing build (no build time)")
    parser.add_argument("--keep", action="store_true", help="leave worktrees and outputs in --work")
    parser.add_argument("--quick", action="store_true", help="fewer cases, no demo (about 2 min)")
    parser.add_argument("--only", help="the steps whose name matches this regular expression (and no others)")
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"))
    parser.add_argument("--harness", default=os.path.join(ROOT, "..", "shared", "harness"))
    parser.add_argument("--self-check", action="store_true", help="test the comparison itself and exit")
    args = parser.parse_args()
    if args.self_check:
        return self_check()
    if not args.base:
        parser.error("--base REV is required")
    args.work, args.data, args.harness = (os.path.abspath(p) for p in (args.work, args.data, args.harness))
    os.makedirs(args.work, exist_ok=True)
    created, bad, noisy = [], ["(not run)"], []
    try:
        revs = [(label, rev, git("rev-parse", "--verify", rev + "^{commit}"))
                for label, rev in (("base", args.base), ("head", args.head))]
        built = [prepare(label, rev, commit, args, created) for label, rev, commit in revs]
        sides = [side for side, _ in built]
        start = time.monotonic()
        inputs, harness = make_inputs(args)
        step_list = [s for s in steps(args, inputs, harness) if not args.only or re.search(args.only, s[0])]
        bad, noisy = run_all(sides, step_list, args)
        wall = time.monotonic() - start
    finally:
        if not args.keep:
            cleanup(created)
            if bad == []:
                shutil.rmtree(os.path.join(args.work, "out"), ignore_errors=True)
                shutil.rmtree(os.path.join(args.work, "inputs"), ignore_errors=True)
    print("\nbase %s (%s), head %s (%s)" % (args.base, sides[0]["commit"][:9], args.head, sides[1]["commit"][:9]))
    for side, seconds in built:
        print("clean Release build, %s: %s" % (side["label"],
                                                "%.0f s wall, %.0f s CPU" % seconds if seconds else "reused"))
    print("%d steps in %.0f s (%s, OMP_NUM_THREADS=%d): %s" % (
        len(step_list), wall, "quick" if args.quick else "full", args.threads,
        "all the same" if not bad else "%d not the same: %s" % (len(bad), ", ".join(bad))))
    if noisy:
        print("same files, a report value varying run to run (same*): " + ", ".join(noisy))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
