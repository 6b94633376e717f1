#!/usr/bin/python3
"""Clean Release build time of two revisions, in pairs, down to each translation unit.

usage: /usr/bin/python3 bench/build_time.py --base REV [--head REV] [--pairs 1] [--jobs 2] [--work DIR] [--top 8]

Each revision is checked out with `git worktree add --detach` under --work (default /tmp/build_time) and built
clean as scripts/build.sh does (`cmake -DCMAKE_BUILD_TYPE=Release`, `cmake --build -j JOBS`: everything, tests,
benches and examples). The builds alternate (base, head, then head, base, ...) so that a drift of the machine
falls on both. A compiler launcher records the user + system CPU seconds of every compile (GNU time), so a
difference can be traced to the files that cause it. Prints one line per build (wall, CPU of the whole build,
CPU of the compiles, load average at its start), the means, then the compiles found on one side only and the
--top largest per-file differences of the first pair. Compare wall times only on an idle machine; CPU seconds
bear a second job far better, but not entirely. Needs /usr/bin/time. The worktrees are removed at the end.
"""
import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAUNCHER = """#!/bin/sh
# one line per compile: user and system CPU seconds, then the object file
out=?; prev=
for a in "$@"; do [ "$prev" = "-o" ] && out=$a; prev=$a; done
exec /usr/bin/time -a -o "{log}" -f "%U %S $out" "$@"
"""


def git(*argv):
    return subprocess.run(["git", "-C", ROOT] + list(argv), check=True, capture_output=True, text=True).stdout.strip()


def children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def build(label, commit, args, number):
    """One clean build of commit; returns (wall, CPU, {object: compile CPU seconds})."""
    tree = os.path.join(args.work, label)
    at = subprocess.run(["git", "-C", tree, "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip() \
        if os.path.isdir(tree) else ""
    if at != commit:
        if os.path.isdir(tree):  # left by an interrupted run, maybe at another commit
            subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", tree], capture_output=True)
            shutil.rmtree(tree, ignore_errors=True)
        git("worktree", "add", "--detach", tree, commit)
    out = os.path.join(args.work, "build-%s" % label)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    log, launcher = os.path.join(out, "compiles.log"), os.path.join(out, "launch.sh")
    with open(launcher, "w") as f:
        f.write(LAUNCHER.format(log=log))
    os.chmod(launcher, 0o755)
    load = os.getloadavg()[0]
    start, cpu = time.monotonic(), children_cpu()
    for command in (["cmake", "-S", tree, "-B", out, "-DCMAKE_BUILD_TYPE=Release",
                     "-DCMAKE_CXX_COMPILER_LAUNCHER=" + launcher, "-DCMAKE_C_COMPILER_LAUNCHER=" + launcher],
                    ["cmake", "--build", out, "-j", str(args.jobs)]):
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall, cpu = time.monotonic() - start, children_cpu() - cpu
    compiles = {}
    with open(log) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 3 and not parts[0].startswith("Command"):
                key = re.sub(r".*?CMakeFiles/", "", parts[2])
                compiles[key] = compiles.get(key, 0.0) + float(parts[0]) + float(parts[1])
    print("build %d, %s (%s): %.0f s wall, %.0f s CPU, compiles %.0f s CPU (%d), load %.2f at start"
          % (number, label, commit[:9], wall, cpu, sum(compiles.values()), len(compiles), load), flush=True)
    shutil.rmtree(out, ignore_errors=True)
    return wall, cpu, compiles


def report(runs, top):
    for label in ("base", "head"):
        mine = [r for l, r in runs if l == label]
        print("%s: mean %.0f s wall, %.0f s CPU over %d builds" % (
            label, sum(r[0] for r in mine) / len(mine), sum(r[1] for r in mine) / len(mine), len(mine)))
    base, head = runs[0][1][2], runs[1][1][2]
    for name, one, other in (("base", base, head), ("head", head, base)):
        only = {k: v for k, v in one.items() if k not in other}
        print("compiles only in %s: %.1f s CPU: %s" % (name, sum(only.values()), ", ".join(
            "%s %.1f" % (k, v) for k, v in sorted(only.items(), key=lambda x: -x[1]))))
    change = sorted(((head[k] - base[k], k) for k in base if k in head), reverse=True)
    print("shared compiles: %.1f s CPU more in head; largest changes (first pair): %s" % (
        sum(d for d, _ in change), ", ".join("%s %+.1f" % (k, d) for d, k in change[:top] + change[-top:])))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--base", required=True, help="the revision before (any git revision)")
    parser.add_argument("--head", default="HEAD", help="the revision after (default HEAD)")
    parser.add_argument("--pairs", type=int, default=1, help="pairs of builds, alternating which goes first")
    parser.add_argument("--jobs", type=int, default=2, help="build jobs (cmake --build -j)")
    parser.add_argument("--work", default="/tmp/build_time")
    parser.add_argument("--top", type=int, default=8, help="per-file differences to print at each end")
    args = parser.parse_args()
    if args.pairs < 1 or args.jobs < 1 or args.top < 0:
        parser.error("--pairs and --jobs must be at least 1, --top at least 0")
    if not os.access("/usr/bin/time", os.X_OK):
        sys.exit("build_time: /usr/bin/time is needed (Debian package time)")
    args.work = os.path.abspath(args.work)
    os.makedirs(args.work, exist_ok=True)
    commits = {label: git("rev-parse", "--verify", rev + "^{commit}")
               for label, rev in (("base", args.base), ("head", args.head))}
    runs = []
    try:
        for pair in range(args.pairs):
            for label in (("base", "head") if pair % 2 == 0 else ("head", "base")):
                runs.append((label, build(label, commits[label], args, len(runs) + 1)))
    finally:
        for label in commits:
            tree = os.path.join(args.work, label)
            if os.path.isdir(tree):
                git("worktree", "remove", "--force", tree)
    report(runs, args.top)
    return 0


if __name__ == "__main__":
    sys.exit(main())
