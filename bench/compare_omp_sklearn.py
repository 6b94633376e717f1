#!/usr/bin/python3
"""Our Batch-OMP vs scikit-learn's orthogonal_mp_gram, in one run on the same data.

Both implement Batch-OMP (Rubinstein, Zibulevsky & Elad, Technion CS-2008-08): a precomputed Gram
matrix G = DᵀD, correlations Dᵀx, progressive Cholesky of G_II, no explicit residual. For every
dictionary size K and sparsity S the script

  * draws a seeded random Gaussian dictionary D (n × K, unit-norm atoms) and P random Gaussian
    signals X (n × P) with numpy, and writes them as raw little-endian float64 (column-major);
  * times our batchOMP through bench/omp_driver (one OpenMP thread) and
    sklearn.linear_model.orthogonal_mp_gram(Gram=DᵀD, Xy=DᵀX, n_nonzero_coefs=S) (BLAS limited to
    one thread) alternately, REPEATS times each, and keeps each side's best wall time;
  * checks that the two codings agree: same support per signal, and the largest coefficient
    difference on the signals whose supports agree.

Timed on both sides: Dᵀx and the OMP iterations (plus assembling our sparse result / sklearn's
dense one). Not timed on either side: DᵀD (once per dictionary) and data I/O.

Run it through compare_omp_sklearn.sh, which installs Debian's python3-sklearn and compiles the
driver. Must run under Debian's /usr/bin/python3 (the python3 first on PATH has no sklearn).
"""

import os

# Before numpy is imported: BLAS libraries read their thread counts at load time. threadpoolctl,
# when present, limits them again below (and tells us which BLAS numpy uses).
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_variable] = "1"

import argparse  # noqa: E402
import contextlib  # noqa: E402
import datetime  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402
import sklearn  # noqa: E402
from sklearn.linear_model import orthogonal_mp_gram  # noqa: E402

try:
    import threadpoolctl  # noqa: E402
except ImportError:  # the environment variables above are then the only limit
    threadpoolctl = None


def write_raw(path, matrix):
    """Column-major little-endian float64, as the driver reads it."""
    np.asarray(matrix, dtype="<f8").T.tofile(path)


def read_raw(path, rows, cols):
    return np.fromfile(path, dtype="<f8").reshape(cols, rows).T


def blas_description():
    """The BLAS/LAPACK libraries this process has loaded. threadpoolctl does not recognise
    Debian's reference BLAS (the default libblas.so.3 alternative), so read /proc/self/maps."""
    libraries = set()
    try:
        with open("/proc/self/maps") as maps:
            for line in maps:
                path = line.split()[-1]
                name = os.path.basename(path)
                if path.startswith("/") and name.startswith("lib") and ("blas" in name or "lapack" in name):
                    libraries.add(os.path.realpath(path))
    except OSError:
        pass
    if threadpoolctl is not None:
        for pool in threadpoolctl.threadpool_info():
            if pool.get("user_api") == "blas":
                libraries.add("{} {}".format(pool.get("internal_api"), pool.get("version") or ""))
    return ", ".join(sorted(libraries)) or "unknown"


def single_thread_blas():
    if threadpoolctl is None:
        return contextlib.nullcontext()
    return threadpoolctl.threadpool_limits(limits=1)


def time_sklearn(dictionary, gram, signals, sparsity):
    """One timed sklearn coding; returns (seconds, K × P codes, signals stopped early)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        start = time.perf_counter()
        correlations = dictionary.T @ signals
        codes = orthogonal_mp_gram(gram, correlations, n_nonzero_coefs=sparsity)
        seconds = time.perf_counter() - start
    return seconds, codes, sum("prematurely" in str(w.message) for w in caught)


def time_product(dictionary, signals, repeats):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        product = dictionary.T @ signals
        best = min(best, time.perf_counter() - start)
    del product
    return best


def run_driver(driver, workdir, n, atoms, count, sparsity):
    """Two timed calls of our batchOMP in one driver process, as sklearn's calls run in this warm
    process: returns (the better call's seconds, the first call's seconds, K × P codes). The first
    call pays for the process's cold memory (its signals never read before)."""
    codes_path = os.path.join(workdir, "codes_K{}_S{}.f64".format(atoms, sparsity))
    environment = dict(os.environ, OMP_NUM_THREADS="1")
    result = subprocess.run(
        [driver, os.path.join(workdir, "D_K{}.f64".format(atoms)), os.path.join(workdir, "X.f64"),
         str(n), str(atoms), str(count), str(sparsity), "2", codes_path],
        env=environment, check=True, capture_output=True, text=True)
    timing = json.loads(result.stdout)
    return timing["best_seconds"], timing["seconds"][0], read_raw(codes_path, atoms, count)


def agreement(ours, theirs):
    """Fraction of signals with identical supports; max |Δcoefficient| over those signals."""
    same = np.all((ours != 0) == (theirs != 0), axis=0)
    if not same.any():
        return 0.0, float("nan")
    return float(same.mean()), float(np.max(np.abs(ours[:, same] - theirs[:, same])))


def load_average():
    try:
        return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    except OSError:
        return "n/a"


def cpu_model():
    try:
        with open("/proc/cpuinfo") as info:
            for line in info:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--driver", required=True, help="the compiled bench/omp_driver")
    parser.add_argument("--output", help="also write the Markdown report here")
    parser.add_argument("--dimension", type=int, default=256)
    parser.add_argument("--atoms", type=int, nargs="+", default=[100, 500])
    parser.add_argument("--sparsity", type=int, nargs="+", default=[5, 20])
    parser.add_argument("--signals", type=int, default=10000)
    parser.add_argument("--repeats", type=int, default=3, help="timings per side; the best counts")
    parser.add_argument("--seed", type=int, default=2008)
    args = parser.parse_args()

    n, count = args.dimension, args.signals
    load_before = load_average()
    rows, notes = [], []
    with tempfile.TemporaryDirectory(prefix="omp_vs_sklearn_") as workdir, single_thread_blas():
        rng = np.random.default_rng(args.seed)
        signals = rng.standard_normal((n, count))
        write_raw(os.path.join(workdir, "X.f64"), signals)
        for atoms in args.atoms:
            dictionary = rng.standard_normal((n, atoms))
            dictionary /= np.linalg.norm(dictionary, axis=0)
            write_raw(os.path.join(workdir, "D_K{}.f64".format(atoms)), dictionary)
            gram = dictionary.T @ dictionary
            product_seconds = time_product(dictionary, signals, args.repeats)
            notes.append("numpy Dᵀx alone, K = {}: {:.1f} ms (inside the sklearn timings)".format(
                atoms, 1e3 * product_seconds))
            for sparsity in args.sparsity:
                # Alternate the two sides, so that load from other processes on a shared machine
                # hits both alike; the best time of each side counts.
                ours_seconds = theirs_seconds = first_seconds = float("inf")
                for _ in range(args.repeats):
                    seconds, first, ours = run_driver(args.driver, workdir, n, atoms, count, sparsity)
                    ours_seconds = min(ours_seconds, seconds)
                    first_seconds = min(first_seconds, first)
                    seconds, theirs, premature = time_sklearn(dictionary, gram, signals, sparsity)
                    theirs_seconds = min(theirs_seconds, seconds)
                same, max_difference = agreement(ours, theirs)
                if premature:
                    notes.append("K = {}, S = {}: sklearn stopped early on {} signals (linear dependence)".format(
                        atoms, sparsity, premature))
                rows.append((atoms, sparsity, count / ours_seconds, count / first_seconds, count / theirs_seconds,
                             theirs_seconds / ours_seconds, same, max_difference))
                print("K={} S={}: ours {:.3f} s, sklearn {:.3f} s, same support {:.2%}, max |dcoef| {:.2e}".format(
                    atoms, sparsity, ours_seconds, theirs_seconds, same, max_difference), file=sys.stderr)

    lines = [
        "# Batch-OMP: pcl_patchdict vs scikit-learn",
        "",
        "{} UTC; n = {}, {} random Gaussian signals, random Gaussian unit-norm dictionaries (seed {}); "
        "one thread on each side; best of {} alternating wall times (ours: the better of two calls in one "
        "process, as sklearn's calls share this warm process; the first call apart); Dᵀx included, DᵀD not.".format(
            datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M"), n, count, args.seed, args.repeats),
        "",
        "| K | S | ours (patches/s) | ours, a process's first call | sklearn (patches/s) | speed-up | same support "
        "| max abs coef diff |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for atoms, sparsity, ours_rate, first_rate, theirs_rate, speedup, same, max_difference in rows:
        lines.append("| {} | {} | {:,.0f} | {:,.0f} | {:,.0f} | {:.1f}x | {:.2%} | {:.1e} |".format(
            atoms, sparsity, ours_rate, first_rate, theirs_rate, speedup, same, max_difference))
    lines += [
        "",
        "- machine: {} cores, {}; load average before {}, after {}".format(
            os.cpu_count(), cpu_model(), load_before, load_average()),
        "- scikit-learn {}, numpy {}, Python {}; BLAS: {}".format(
            sklearn.__version__, np.__version__, platform.python_version(), blas_description()),
        "- max abs coef diff: over the signals whose supports agree",
    ]
    lines += ["- " + note for note in notes]
    report = "\n".join(lines) + "\n"
    print(report)
    if args.output:
        os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
        with open(args.output, "w") as out:
            out.write(report)
    worst = min(row[6] for row in rows)
    if worst < 0.99:
        print("WARNING: supports agree on only {:.2%} of the signals (< 99 %)".format(worst), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
