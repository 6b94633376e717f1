#!/usr/bin/python3
"""The cloud repairs on real sensor scans (../shared/data/real): holes punched where the truth is known,
whole scans, denoising roughness, an airborne LiDAR tile. Every definition is implemented here.

  1 holes      each Kinect scan x seed: 8 discs of 6-20 px punched in image space, each on one surface (the
               disc and a 2-px ring valid, their depth spread < 3 % of the median, discs with rings not
               touching; numpy default_rng(seed)); `fill-holes` against a harmonic image-space fill, scored.
  2 whole      `fill-holes` and `denoise` on each whole Kinect scan: seconds, added points, free-space
               violations, width x height kept.
  3 roughness  RMS residual of 5 cm neighbourhoods of the largest plane (RANSAC on the input, 1.5 cm,
               500 seeded tries; 4000 seeded points) to their own planes: input, `denoise`, PCL's MLS.
  4 lidar      terrain_csite3 x seed: 8 vertical cylinders of --radius-m punched through; `fill-holes`
               (seconds, peak RSS) against a rasterised harmonic grid fill, scored.

Scores (distances in the cloud's units, then divided by the local spacing s, the median distance to the
input's nearest points at that place, computed as the harness does: the 5 nearest input points, the
nearest dropped):
  added            output points farther than 1e-6 x the input's extent from every input point
  coverage         share of the removed real points within 1.5 s of an added point
  removed_to_out   mean distance of the removed points to the nearest added point, / s (each capped at 1000)
  in holes         added points projecting within 1.5 px of a punched disc (organised) or within 2 s of a
                   cylinder (LiDAR, in xy); "outside" = the rest
  free space       added points projecting onto a pixel whose 3 x 3 neighbourhood's nearest measured depth is
                   more than max(3 s, 1 % of that depth) behind them: space the sensor saw through

usage: bench/real_scans.py [--quick] [--seeds 1,2,3] [--radius-m 8,25] [--shared ../shared/data]
                           [--tool build/pcl_patchdict] [--out bench/results/real_scans] [--work DIR]
--quick: mosd_learn0 with seed 1, the LiDAR tile with seed 1, no MLS at 3 cm (30-50 s on 2 cores).
Writes OUT/real_scans.md (tables, commands, commit), OUT/{holes,whole,roughness,lidar}.csv and
OUT/real_scans.log (each command and its stderr). Only numpy and scipy; binary_compressed PCDs are first
converted with `pcl_convert_pcd_ascii_binary IN OUT 1` (pcl-tools), as is `pcl_mls_smoothing`.
"""
import argparse
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree

from reproduce import git_commit  # noqa: E402  (the same "commit (with uncommitted changes)" line)

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
ORGANISED = ["mosd_learn0", "mosd_learn20", "mosd_learn28", "mosd_learn40", "kinect_frame_142256"]
LIDAR = "terrain_csite3"
MLS_RADII = [0.01, 0.02, 0.03]
HOLES, RADIUS_PX, MAX_FILL_PX, MAX_FILL_CELLS, CELL_FACTOR = 8, (6, 20), 2000, 4000, 1.5
PLANE_THRESHOLD, PLANE_TRIES, ROUGHNESS_RADIUS, ROUGHNESS_POINTS = 0.015, 500, 0.05, 4000


# ---------------------------------------------------------------- PCD files

def read_pcd(path, work):
    """-> (structured array of every field, {'width', 'height', 'viewpoint'}); ascii or binary, and
    binary_compressed through pcl_convert_pcd_ascii_binary into `work`."""
    with open(path, "rb") as f:
        data = f.read()
    header, offset = {}, 0
    while True:
        end = data.index(b"\n", offset)
        line = data[offset:end].decode("ascii", "replace").strip()
        offset = end + 1
        if line and not line.startswith("#"):
            key, *values = line.split()
            header[key.upper()] = values
            if key.upper() == "DATA":
                break
    mode = header["DATA"][0]
    if mode == "binary_compressed":
        plain = Path(work) / ("plain_" + Path(path).name)
        subprocess.run(["pcl_convert_pcd_ascii_binary", str(path), str(plain), "1"], check=True,
                       capture_output=True)
        result = read_pcd(plain, work)
        plain.unlink()
        return result
    fields, sizes, types = header["FIELDS"], [int(s) for s in header["SIZE"]], header["TYPE"]
    counts = [int(c) for c in header.get("COUNT", ["1"] * len(fields))]
    n = int(header["POINTS"][0])
    dtype = np.dtype([((name if name != "_" else "_pad%d" % k), "<%s%d" % ({"F": "f", "U": "u", "I": "i"}[t], s))
                      + (((c,),) if c > 1 else ()) for k, (name, s, t, c) in enumerate(zip(fields, sizes, types,
                                                                                           counts))])
    if mode == "binary":
        arr = np.frombuffer(data[offset:offset + n * dtype.itemsize], dtype).copy()
    elif mode == "ascii":
        table = np.array([ln.split() for ln in data[offset:].decode().splitlines() if ln.strip()], np.float64)
        arr, column = np.zeros(n, dtype), 0
        for name, c in zip(dtype.names, counts):
            arr[name] = table[:, column] if c == 1 else table[:, column:column + c]
            column += c
    else:
        sys.exit("real_scans.py: %s: unsupported PCD DATA %s" % (path, mode))
    return arr, {"width": int(header["WIDTH"][0]), "height": int(header["HEIGHT"][0]),
                 "viewpoint": header.get("VIEWPOINT", ["0", "0", "0", "1", "0", "0", "0"])}


def write_pcd(path, arr, width, height, viewpoint):
    """Binary PCD with the array's fields (padding fields written back as `_`)."""
    fields, sizes, types, counts = [], [], [], []
    for name in arr.dtype.names:
        base = arr.dtype[name].base
        fields.append("_" if name.startswith("_pad") else name)
        sizes.append(str(base.itemsize))
        types.append({"f": "F", "u": "U", "i": "I"}[base.kind])
        counts.append(str(int(np.prod(arr.dtype[name].shape)) if arr.dtype[name].shape else 1))
    head = ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS %s\nSIZE %s\nTYPE %s\nCOUNT %s\n"
            "WIDTH %d\nHEIGHT %d\nVIEWPOINT %s\nPOINTS %d\nDATA binary\n") % (
        " ".join(fields), " ".join(sizes), " ".join(types), " ".join(counts), width, height, " ".join(viewpoint),
        len(arr))
    with open(path, "wb") as f:
        f.write(head.encode())
        f.write(np.ascontiguousarray(arr).tobytes())


def xyz(arr):
    return np.stack([arr["x"], arr["y"], arr["z"]], 1).astype(np.float64)


def finite_rows(P):
    return np.isfinite(P).all(1)


# ---------------------------------------------------------------- geometry shared by the scores

def fit_camera(P, width, height):
    """Pinhole camera of an organised cloud by least squares: column = fx x/z + cx, row = fy y/z + cy."""
    rows, cols = np.divmod(np.arange(width * height), width)
    ok = finite_rows(P) & (P[:, 2] > 0)
    cam = {}
    for axis, k, pixel in (("x", 0, cols), ("y", 1, rows)):
        a = P[ok, k] / P[ok, 2]
        (f, c), *_ = np.linalg.lstsq(np.stack([a, np.ones_like(a)], 1), pixel[ok].astype(np.float64), rcond=None)
        cam["f" + axis], cam["c" + axis] = float(f), float(c)
    return cam


def spacing_at(tree, Q, k=4):
    """The local spacing at Q: the median of the distances to the k+1 nearest input points, the nearest
    dropped (the point itself when Q is an input point) — the harness's rule, kept for comparable scores."""
    d, _ = tree.query(Q, k + 1, workers=2)
    return np.median(d[:, 1:], axis=1)


def split_added(P_in, P_out):
    """-> (finite input, its tree, finite output, the output points that are not input points)."""
    fin = P_in[finite_rows(P_in)]
    out = P_out[finite_rows(P_out)]
    tree = cKDTree(fin)
    d, _ = tree.query(out, workers=2)
    return fin, tree, out, out[d > 1e-6 * np.ptp(fin, axis=0).max()]


def free_space_violations(P_in, width, height, added, cam, tree_in):
    """Added points in front of the nearest measured depth of their pixel's 3 x 3 neighbourhood by more
    than max(3 s, 1 % of that depth)."""
    if len(added) == 0:
        return 0
    depth = np.where(finite_rows(P_in), P_in[:, 2], np.inf).reshape(height, width)
    pad = np.pad(depth, 1, constant_values=np.inf)
    nearest = np.min([pad[1 + dy:1 + dy + height, 1 + dx:1 + dx + width] for dy in (-1, 0, 1) for dx in (-1, 0, 1)],
                     axis=0)
    ahead = added[:, 2] > 0
    z = np.where(ahead, added[:, 2], 1)
    col = np.round(cam["fx"] * added[:, 0] / z + cam["cx"]).astype(np.int64)
    row = np.round(cam["fy"] * added[:, 1] / z + cam["cy"]).astype(np.int64)
    idx = np.flatnonzero(ahead & (col >= 0) & (col < width) & (row >= 0) & (row < height))
    seen = nearest[row[idx], col[idx]]
    s = spacing_at(tree_in, added[idx])
    with np.errstate(invalid="ignore"):
        return int((np.isfinite(seen) & (added[idx, 2] < seen - np.maximum(3 * s, 0.01 * seen))).sum())


def score(P_in, width, height, removed, P_out, in_holes, cam=None):
    """Scores of a fill of the holed input P_in against the removed real points; in_holes(added) -> mask."""
    fin, tree, out, added = split_added(P_in, P_out)
    s_rem = spacing_at(tree, removed)
    d_rem = cKDTree(added).query(removed, workers=2)[0] if len(added) else np.full(len(removed), np.inf)
    d_in = cKDTree(out).query(fin, workers=2)[0]
    inside = int(in_holes(added).sum()) if len(added) else 0
    organised = cam is not None and height > 1 and len(P_in) == width * height
    return {"removed": len(removed), "coverage": float((d_rem <= 1.5 * s_rem).mean()),
            "removed_to_out": float(np.mean(np.minimum(d_rem / s_rem, 1e3))),
            "added": len(added), "added_in_holes": inside, "added_outside_holes": len(added) - inside,
            "free_space_violations": free_space_violations(P_in, width, height, added, cam, tree) if organised
            else "",
            "input_points_lost": int((d_in > 1e-6 * np.ptp(fin, axis=0).max()).sum()),
            "input_points_moved_over_3s": int((d_in > 3 * spacing_at(tree, fin)).sum())}


# ---------------------------------------------------------------- punched holes

def punch_image(arr, width, height, seed):
    """8 discs of NaN in image space, each with its 2-px ring valid and on one surface (depth spread of
    disc + ring < 3 % of its median), disc + ring not touching another's. -> (holed array, removed
    points, holes as (row, col, radius))."""
    P = xyz(arr)
    valid = finite_rows(P).reshape(height, width)
    depth = np.where(valid, P[:, 2].reshape(height, width), np.nan)
    rng = np.random.default_rng(seed)
    taken = np.zeros((height, width), bool)
    holes, tries = [], 0
    while len(holes) < HOLES and tries < 20000:
        tries += 1
        r = int(rng.integers(RADIUS_PX[0], RADIUS_PX[1] + 1))
        cy, cx = int(rng.integers(r + 2, height - r - 2)), int(rng.integers(r + 2, width - r - 2))
        yy, xx = np.ogrid[-r - 2:r + 3, -r - 2:r + 3]
        ring = yy * yy + xx * xx <= (r + 2) * (r + 2)  # the disc and its 2-px ring
        window = (slice(cy - r - 2, cy + r + 3), slice(cx - r - 2, cx + r + 3))
        if not valid[window][ring].all() or taken[window][ring].any():
            continue
        d = depth[window][ring]
        if d.max() - d.min() > 0.03 * np.median(d):
            continue
        taken[window] |= ring
        holes.append((cy, cx, r))
    if len(holes) < HOLES:
        sys.exit("real_scans.py: only %d holes fit on one surface each (seed %d)" % (len(holes), seed))
    yy, xx = np.ogrid[:height, :width]
    mask = np.zeros((height, width), bool)
    for cy, cx, r in holes:
        mask |= (yy - cy) ** 2 + (xx - cx) ** 2 <= r * r
    flat = mask.ravel()
    holed = arr.copy()
    for c in "xyz":
        holed[c][flat] = np.nan
    return holed, P[flat], holes


def lidar_spacing(Q):
    """Median distance to the 4 nearest neighbours over about 20 000 evenly taken points."""
    return float(np.median(cKDTree(Q).query(Q[::max(1, len(Q) // 20000)], 5, workers=2)[0][:, 1:]))


def punch_cylinders(arr, seed, rmin, rmax):
    """8 vertical cylinders punched through an unorganised 2.5-D cloud: each xy-disc with its 3-s margin
    fully sampled (at least half the points of a grid of spacing s), discs 6 s apart.
    -> (holed array of the finite points left, removed points, holes as (cx, cy, radius), spacing)."""
    P = xyz(arr)
    ok = finite_rows(P)
    Q = P[ok]
    tree = cKDTree(Q[:, :2])
    s = lidar_spacing(Q)
    lo, hi = Q[:, :2].min(0), Q[:, :2].max(0)
    rng = np.random.default_rng(seed)
    holes, removed, tries = [], np.zeros(len(Q), bool), 0
    while len(holes) < HOLES and tries < 20000:
        tries += 1
        r = float(rng.uniform(rmin, rmax))
        c = rng.uniform(lo + r + 2 * s, hi - r - 2 * s)
        ring = np.array(tree.query_ball_point(c, r + 3 * s), np.int64)
        if len(ring) < 0.5 * np.pi * ((r + 3 * s) / s) ** 2 or removed[ring].any() or \
                any(np.hypot(c[0] - hx, c[1] - hy) < r + hr + 6 * s for hx, hy, hr in holes):
            continue
        removed[ring[np.hypot(Q[ring, 0] - c[0], Q[ring, 1] - c[1]) <= r]] = True
        holes.append((float(c[0]), float(c[1]), r))
    if len(holes) < HOLES:
        sys.exit("real_scans.py: only %d cylinders fit (seed %d)" % (len(holes), seed))
    return arr[np.flatnonzero(ok)[~removed]], Q[removed], holes, s


# ---------------------------------------------------------------- reference fills

def harmonic_solve(fill, values):
    """Laplace's equation on the True cells of `fill` (none on the border), the other 4-neighbours fixed
    at `values`: 4 u_i - sum of unknown neighbours = sum of known neighbours."""
    h, w = fill.shape
    idx = np.flatnonzero(fill.ravel())
    ids = np.full(h * w, -1, np.int64)
    ids[idx] = np.arange(len(idx))
    rows, cols, vals = [np.arange(len(idx))], [np.arange(len(idx))], [np.full(len(idx), 4.0)]
    b = np.zeros(len(idx))
    flat_fill, flat_values = fill.ravel(), values.ravel()
    for step in (w, -w, 1, -1):
        nb = idx + step
        unknown = flat_fill[nb]
        rows.append(np.flatnonzero(unknown))
        cols.append(ids[nb[unknown]])
        vals.append(np.full(int(unknown.sum()), -1.0))
        b += np.where(unknown, 0.0, flat_values[nb])
    A = sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(len(idx), len(idx)))
    return idx, (spsolve(A.tocsc(), b) if len(idx) else np.zeros(0))


def enclosed_regions(empty, max_size, rim_ok=None):
    """The 4-connected regions of `empty` with at most max_size cells, not touching the border, whose
    rim (the 4-neighbours) passes rim_ok(rim mask of the window, window slices)."""
    h, w = empty.shape
    labels, _ = ndimage.label(empty)
    sizes = np.bincount(labels.ravel())
    fill = np.zeros_like(empty)
    for k, sl in enumerate(ndimage.find_objects(labels), 1):
        if sl is None or sizes[k] > max_size or sl[0].start == 0 or sl[1].start == 0 or sl[0].stop == h \
                or sl[1].stop == w:
            continue
        window = (slice(sl[0].start - 1, sl[0].stop + 1), slice(sl[1].start - 1, sl[1].stop + 1))
        region = labels[window] == k
        if rim_ok is not None and not rim_ok(ndimage.binary_dilation(region) & ~region, window):
            continue
        fill[window] |= region
    return fill


def image_fill(arr, width, height):
    """Harmonic image-space fill: each enclosed NaN region of <= 2000 px whose rim's depth spread is < 3 %
    of its median gets Laplace's equation in depth; x, y from the pinhole camera fitted to the input."""
    P = xyz(arr)
    valid = finite_rows(P).reshape(height, width)
    Z = np.where(valid, P[:, 2].reshape(height, width), 0.0)
    cam = fit_camera(P, width, height)

    def one_surface(rim, window):
        d = Z[window][rim]
        return d.max() - d.min() <= 0.03 * np.median(d)

    idx, z = harmonic_solve(enclosed_regions(~valid, MAX_FILL_PX, one_surface), Z)
    out = arr.copy()
    row, col = np.divmod(idx, width)
    out["z"][idx] = z
    out["x"][idx] = (col - cam["cx"]) * z / cam["fx"]
    out["y"][idx] = (row - cam["cy"]) * z / cam["fy"]
    return out


def grid_fill(arr):
    """Rasterised harmonic fill of a 2.5-D cloud: cells of 1.5 x the median spacing, the empty cells
    forming enclosed 4-connected regions of <= 4000 cells get Laplace's equation in the cells' mean z;
    one point per filled cell at its centre. -> the input's finite points followed by the new ones."""
    P = xyz(arr)
    keep = finite_rows(P)
    arr, P = arr[keep], P[keep]
    cell = CELL_FACTOR * lidar_spacing(P)
    lo = P[:, :2].min(0)
    ij = np.floor((P[:, :2] - lo) / cell).astype(np.int64)
    nx, ny = ij.max(0) + 1
    flat = ij[:, 0] * ny + ij[:, 1]
    count = np.bincount(flat, minlength=nx * ny).reshape(nx, ny)
    total = np.bincount(flat, weights=P[:, 2], minlength=nx * ny).reshape(nx, ny)
    occupied = count > 0
    Z = np.where(occupied, total / np.maximum(count, 1), 0.0)
    idx, z = harmonic_solve(enclosed_regions(~occupied, MAX_FILL_CELLS), Z)
    ci, cj = np.divmod(idx, ny)
    out = np.zeros(len(arr) + len(idx), arr.dtype)
    out[:len(arr)] = arr
    out["x"][len(arr):] = lo[0] + (ci + 0.5) * cell
    out["y"][len(arr):] = lo[1] + (cj + 0.5) * cell
    out["z"][len(arr):] = z
    return out


# ---------------------------------------------------------------- plane roughness

def largest_plane(P):
    """RANSAC: 500 tries of 3 points (default_rng(0)), the plane with the most points within 1.5 cm."""
    rng = np.random.default_rng(0)
    best = (0, None)
    for _ in range(PLANE_TRIES):
        s = P[rng.choice(len(P), 3, replace=False)]
        n = np.cross(s[1] - s[0], s[2] - s[0])
        norm = np.linalg.norm(n)
        if norm == 0:
            continue
        n /= norm
        d = -n @ s[0]
        count = int((np.abs(P @ n + d) < PLANE_THRESHOLD).sum())
        if count > best[0]:
            best = (count, (n, d))
    return best[1]


def roughness_mm(P, plane):
    """RMS residual (mm) of the 5 cm neighbourhoods (>= 10 points) of 4000 seeded points of the cloud's
    points within 1.5 cm of the plane, each to its own least-squares plane. -> (mm, region points)."""
    n, d = plane
    region = P[np.abs(P @ n + d) < PLANE_THRESHOLD]
    tree = cKDTree(region)
    q = region[np.random.default_rng(1).choice(len(region), min(ROUGHNESS_POINTS, len(region)), replace=False)]
    squares, count = 0.0, 0
    for nb in tree.query_ball_point(q, ROUGHNESS_RADIUS, workers=2):
        if len(nb) < 10:
            continue
        X = region[nb] - region[nb].mean(0)
        squares += np.linalg.eigh(X.T @ X)[0][0]
        count += len(nb)
    return 1000 * float(np.sqrt(squares / max(count, 1))), len(region)


# ---------------------------------------------------------------- running

class Runner:
    def __init__(self, log):
        self.log = log

    def __call__(self, command, env=None):
        """Runs a command; -> (wall seconds, peak RSS of the child in MB, stdout)."""
        command = [str(c) for c in command]
        with open(self.log, "a") as log, tempfile.TemporaryFile() as stdout:
            log.write("$ " + " ".join(command) + "\n")
            log.flush()
            # /usr/bin/time measures the peak RSS: a child forked from this process would count the pages it
            # shares with it until its exec
            peak_file = tempfile.NamedTemporaryFile(suffix=".txt", delete=False).name
            start = time.monotonic()
            child = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", peak_file, *command], stdout=stdout,
                                   stderr=log, env=env)
            seconds = time.monotonic() - start
            stdout.seek(0)
            text = stdout.read().decode()
            with open(peak_file) as f:
                peak = f.read().split()
            os.unlink(peak_file)
        if child.returncode != 0:
            sys.exit("real_scans.py: failed (exit %d): %s — see %s" % (child.returncode, " ".join(command), self.log))
        return seconds, float(peak[-1]) / 1024.0 if peak else float("nan"), text


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def fmt(v, digits=3):
    return "%.*f" % (digits, v) if isinstance(v, float) else str(v)


def holes_step(a, run, work, scans, seeds):
    rows = []
    for name in scans:
        arr, info = read_pcd(a.real / (name + ".pcd"), work)
        W, H = info["width"], info["height"]
        cam = fit_camera(xyz(arr), W, H)  # the scorer's camera: from the whole scan
        for seed in seeds:
            case = work / ("%s_seed%d" % (name, seed))
            case.mkdir(exist_ok=True)
            holed, removed, holes = punch_image(arr, W, H, seed)
            write_pcd(case / "holed.pcd", holed, W, H, info["viewpoint"])
            seconds, _, text = run([a.tool, "fill-holes", case / "holed.pcd", "-o", case / "out.pcd", "--json"])
            start = time.monotonic()
            reference = image_fill(holed, W, H)
            ref_seconds = time.monotonic() - start
            write_pcd(case / "image_fill.pcd", reference, W, H, info["viewpoint"])
            P_in = xyz(holed)

            def in_holes(added):
                col = cam["fx"] * added[:, 0] / added[:, 2] + cam["cx"]
                row = cam["fy"] * added[:, 1] / added[:, 2] + cam["cy"]
                return np.any([(row - cy) ** 2 + (col - cx) ** 2 <= (r + 1.5) ** 2 for cy, cx, r in holes], axis=0)

            ours = score(P_in, W, H, removed, xyz(read_pcd(case / "out.pcd", work)[0]), in_holes, cam)
            ref = score(P_in, W, H, removed, xyz(reference), in_holes, cam)
            row = {"scan": name, "seed": seed, "removed": len(removed), "seconds": round(seconds, 3),
                   "image_fill_seconds": round(ref_seconds, 3)}
            for key in ("coverage", "removed_to_out", "added", "added_in_holes", "added_outside_holes",
                        "free_space_violations", "input_points_lost", "input_points_moved_over_3s"):
                row[key], row["image_fill_" + key] = ours[key], ref[key]
            rows.append(row)
            print("holes  %-20s seed %d: coverage %.3f / %.3f, removed->out %.3f / %.3f s, added %d / %d "
                  "(outside %d / %d), free space %d / %d, %.2f s" % (
                      name, seed, row["coverage"], row["image_fill_coverage"], row["removed_to_out"],
                      row["image_fill_removed_to_out"], row["added"], row["image_fill_added"],
                      row["added_outside_holes"], row["image_fill_added_outside_holes"],
                      row["free_space_violations"], row["image_fill_free_space_violations"], seconds), flush=True)
            if not a.keep:
                shutil.rmtree(case)
    write_csv(a.out / "holes.csv", rows)
    md = ["| scan | seed | removed | coverage ours / image fill | removed→out (s) ours / image fill | added ours / "
          "image fill | added outside the holes | free-space violations | seconds ours / image fill |",
          "|---|---:|---:|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %d | %d | %.3f / %.3f | %.3f / %.3f | %d / %d | %d / %d | %d / %d | %.2f / %.2f |" % (
            r["scan"], r["seed"], r["removed"], r["coverage"], r["image_fill_coverage"], r["removed_to_out"],
            r["image_fill_removed_to_out"], r["added"], r["image_fill_added"], r["added_outside_holes"],
            r["image_fill_added_outside_holes"], r["free_space_violations"], r["image_fill_free_space_violations"],
            r["seconds"], r["image_fill_seconds"]))
    return md


def whole_step(a, run, work, scans):
    rows, denoised = [], {}
    for name in scans:
        src = work / (name + ".pcd")
        arr, info = read_pcd(a.real / (name + ".pcd"), work)
        W, H = info["width"], info["height"]
        write_pcd(src, arr, W, H, info["viewpoint"])  # binary: what the tools are given
        P_in = xyz(arr)
        cam = fit_camera(P_in, W, H)
        row = {"scan": name, "points": int(finite_rows(P_in).sum())}
        for command in ("fill-holes", "denoise"):
            out = work / ("%s_%s.pcd" % (name, command))
            seconds, peak, _ = run([a.tool, command, src, "-o", out, "--json"])
            out_arr, out_info = read_pcd(out, work)
            fin, tree, _, added = split_added(P_in, xyz(out_arr))
            key = command.replace("-", "_")
            row.update({key + "_seconds": round(seconds, 3), key + "_peak_mb": round(peak, 1),
                        key + "_not_input_points": len(added),
                        key + "_free_space_violations": free_space_violations(P_in, W, H, added, cam, tree),
                        key + "_kept_grid": int((out_info["width"], out_info["height"]) == (W, H)),
                        key + "_width_x_height": "%d×%d" % (out_info["width"], out_info["height"])})
            if command == "denoise":
                denoised[name] = (out, seconds)
        row["image_fill_added"] = len(split_added(P_in, xyz(image_fill(arr, W, H)))[3])
        rows.append(row)
        print("whole  %-20s fill-holes %.2f s, %d added (image fill %d), %d free-space; denoise %.1f s, %d moved "
              "or new, %d free-space; %s / %s" % (
                  name, row["fill_holes_seconds"], row["fill_holes_not_input_points"], row["image_fill_added"],
                  row["fill_holes_free_space_violations"], row["denoise_seconds"], row["denoise_not_input_points"],
                  row["denoise_free_space_violations"], row["fill_holes_width_x_height"],
                  row["denoise_width_x_height"]), flush=True)
    write_csv(a.out / "whole.csv", rows)
    md = ["| scan | points | `fill-holes` s | added (image fill) | free-space violations | W×H out | `denoise` s | "
          "points moved or new | free-space violations | W×H out |", "|---|---:|---:|---:|---:|---|---:|---:|---:|---|"]
    for r in rows:
        md.append("| %s | %d | %.2f | %d (%d) | %d | %s | %.1f | %d | %d | %s |" % (
            r["scan"], r["points"], r["fill_holes_seconds"], r["fill_holes_not_input_points"], r["image_fill_added"],
            r["fill_holes_free_space_violations"], r["fill_holes_width_x_height"], r["denoise_seconds"],
            r["denoise_not_input_points"], r["denoise_free_space_violations"], r["denoise_width_x_height"]))
    return md, denoised


def roughness_step(a, run, work, scans, denoised, radii):
    rows = []
    env = dict(os.environ, OMP_NUM_THREADS="2")
    for name in scans:
        src = work / (name + ".pcd")
        P0 = xyz(read_pcd(src, work)[0])
        P0 = P0[finite_rows(P0)]
        plane = largest_plane(P0)
        base, region = roughness_mm(P0, plane)
        row = {"scan": name, "plane_points": region, "input_mm": round(base, 4)}
        out, seconds = denoised[name]
        clouds = [("denoise", out, seconds)]
        for radius in radii:
            mls = work / ("%s_mls%g.pcd" % (name, radius))
            seconds, _, _ = run(["pcl_mls_smoothing", src, mls, "-radius", radius], env=env)
            clouds.append(("mls_%gcm" % (100 * radius), mls, seconds))
        for key, path, seconds in clouds:
            P = xyz(read_pcd(path, work)[0])
            mm = roughness_mm(P[finite_rows(P)], plane)[0]
            row.update({key + "_mm": round(mm, 4), key + "_below_input_pct": round(100 * (1 - mm / base), 1),
                        key + "_seconds": round(seconds, 2)})
        rows.append(row)
        print("rough  %-20s " % name + ", ".join("%s %.3f mm" % (k[:-3], v) for k, v in row.items()
                                                   if k.endswith("_mm")), flush=True)
    write_csv(a.out / "roughness.csv", rows)
    keys = ["denoise"] + ["mls_%gcm" % (100 * r) for r in radii]
    md = ["| scan | plane points | input mm | " + " | ".join(
        "`denoise`" if k == "denoise" else "MLS %s cm" % k[4:-2] for k in keys) + " |",
        "|---|---:|---:|" + "---:|" * len(keys)]
    for r in rows:
        md.append("| %s | %d | %.3f | " % (r["scan"], r["plane_points"], r["input_mm"]) + " | ".join(
            "%.3f (−%.1f %%, %.1f s)" % (r[k + "_mm"], r[k + "_below_input_pct"], r[k + "_seconds"]) for k in keys)
            + " |")
    return md


def lidar_step(a, run, work, seeds, rmin, rmax):
    rows = []
    arr, info = read_pcd(a.real / (LIDAR + ".pcd"), work)
    for seed in seeds:
        case = work / ("%s_seed%d" % (LIDAR, seed))
        case.mkdir(exist_ok=True)
        holed, removed, holes, s = punch_cylinders(arr, seed, rmin, rmax)
        write_pcd(case / "holed.pcd", holed, len(holed), 1, info["viewpoint"])
        seconds, peak, _ = run([a.tool, "fill-holes", case / "holed.pcd", "-o", case / "out.pcd", "--json"])
        start = time.monotonic()
        reference = grid_fill(holed)
        ref_seconds = time.monotonic() - start
        write_pcd(case / "grid_fill.pcd", reference, len(reference), 1, info["viewpoint"])
        P_in = xyz(holed)

        def in_holes(added):
            return np.any([np.hypot(added[:, 0] - hx, added[:, 1] - hy) <= hr + 2 * s for hx, hy, hr in holes],
                          axis=0)

        ours = score(P_in, len(holed), 1, removed, xyz(read_pcd(case / "out.pcd", work)[0]), in_holes)
        ref = score(P_in, len(holed), 1, removed, xyz(reference), in_holes)
        row = {"seed": seed, "radius_m": "%g-%g" % (rmin, rmax), "removed": len(removed),
               "seconds": round(seconds, 3), "peak_mb": round(peak, 1), "grid_fill_seconds": round(ref_seconds, 3)}
        for key in ("coverage", "removed_to_out", "added", "added_in_holes", "added_outside_holes",
                    "input_points_lost", "input_points_moved_over_3s"):
            row[key], row["grid_fill_" + key] = ours[key], ref[key]
        rows.append(row)
        print("lidar  seed %d: coverage %.3f / %.3f, removed->out %.3f / %.3f s, added %d (%d in holes) / %d (%d), "
              "%.2f s, %.0f MB" % (seed, row["coverage"], row["grid_fill_coverage"], row["removed_to_out"],
                                   row["grid_fill_removed_to_out"], row["added"], row["added_in_holes"],
                                   row["grid_fill_added"], row["grid_fill_added_in_holes"], seconds, peak), flush=True)
        if not a.keep:
            shutil.rmtree(case)
    write_csv(a.out / "lidar.csv", rows)
    md = ["| seed | removed | coverage ours / grid | removed→out (s) ours / grid | added (in holes) ours | "
          "added (in holes) grid | seconds ours / grid | peak RSS ours |", "|---:|---:|---|---|---:|---:|---|---:|"]
    for r in rows:
        md.append("| %d | %d | %.3f / %.3f | %.3f / %.3f | %d (%d) | %d (%d) | %.2f / %.2f | %.0f MB |" % (
            r["seed"], r["removed"], r["coverage"], r["grid_fill_coverage"], r["removed_to_out"],
            r["grid_fill_removed_to_out"], r["added"], r["added_in_holes"], r["grid_fill_added"],
            r["grid_fill_added_in_holes"], r["seconds"], r["grid_fill_seconds"], r["peak_mb"]))
    return md


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--seeds", default="1,2,3")
    parser.add_argument("--radius-m", default="8,25", help="LiDAR cylinder radii, min,max (cloud units)")
    parser.add_argument("--shared", default=str(ROOT.parent / "shared" / "data"))
    parser.add_argument("--tool", default=str(ROOT / "build" / "pcl_patchdict"))
    parser.add_argument("--out", default=str(HERE / "results" / "real_scans"))
    parser.add_argument("--work", help="keep the intermediate clouds here (default: a temporary folder)")
    a = parser.parse_args()
    a.real, a.tool, a.out = Path(a.shared).resolve() / "real", Path(a.tool).resolve(), Path(a.out).resolve()
    if not a.real.is_dir():
        sys.exit("real_scans.py: %s not found — the scans live in ../shared/data/real" % a.real)
    if not a.tool.exists():
        sys.exit("real_scans.py: %s not built — run scripts/build.sh first" % a.tool)
    for program in ("pcl_convert_pcd_ascii_binary", "pcl_mls_smoothing", "/usr/bin/time"):
        if shutil.which(program) is None:
            sys.exit("real_scans.py: %s not found (Debian's pcl-tools)" % program)
    a.out.mkdir(parents=True, exist_ok=True)
    a.keep = a.work is not None
    work = Path(a.work).resolve() if a.keep else Path(tempfile.mkdtemp(prefix="real_scans_"))
    work.mkdir(parents=True, exist_ok=True)
    seeds = [int(s) for s in a.seeds.split(",") if s]
    scans, radii = ORGANISED, MLS_RADII
    if a.quick:
        seeds, scans, radii = seeds[:1], ORGANISED[:1], MLS_RADII[:2]
    rmin, rmax = (float(v) for v in a.radius_m.split(","))
    log = a.out / "real_scans.log"
    log.write_text("# real_scans.py %s\n" % " ".join(sys.argv[1:]))
    run = Runner(log)
    commit = git_commit()
    start = time.monotonic()
    try:
        steps = []
        t = time.monotonic()
        holes_md = holes_step(a, run, work, scans, seeds)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        whole_md, denoised = whole_step(a, run, work, scans)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        rough_md = roughness_step(a, run, work, scans, denoised, radii)
        steps.append(time.monotonic() - t)
        t = time.monotonic()
        lidar_md = lidar_step(a, run, work, seeds, rmin, rmax)
        steps.append(time.monotonic() - t)
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    seconds = time.monotonic() - start
    tool = "pcl_patchdict"
    md = ["# Real sensor scans", "",
          "*`bench/real_scans.py%s`, commit %s, %s UTC, %.0f s (steps %s s); `%s` built %s UTC; scans from "
          "`%s`.*" % (" --quick" if a.quick else "", commit, time.strftime("%Y-%m-%d %H:%M", time.gmtime()), seconds,
                      " / ".join("%.0f" % s for s in steps), a.tool.name,
                      time.strftime("%Y-%m-%d %H:%M", time.gmtime(a.tool.stat().st_mtime)), a.real),
          "",
          "s is the local spacing (median distance to the nearby input points). Added: output points that are not "
          "input points (to 1e-6 of the extent). Free-space violation: an added point in front of the nearest "
          "measured depth of its pixel's 3×3 neighbourhood by more than max(3 s, 1 % of that depth). Seconds are "
          "wall time of the whole command (load, work, write) on a shared 2-core machine.", "",
          "### 1. Punched holes, organised Kinect scans", "",
          "8 discs of 6–20 px per case, each on one surface (disc and 2-px ring valid, depth spread < 3 %%), "
          "`numpy.random.default_rng(seed)`; the removed real points are the truth. "
          "Commands: `%s fill-holes holed.pcd -o out.pcd --json`; the reference is this script's harmonic "
          "image-space fill (Laplace in depth over each enclosed NaN region of ≤ 2000 px with rim spread < 3 %%; "
          "x, y on the fitted pinhole camera's rays; timed in-process). Coverage: share of removed points "
          "within 1.5 s of an added point; removed→out: their mean distance to the nearest added point / s; "
          "outside the holes: added points projecting farther than 1.5 px from every disc." % tool, ""] + holes_md + [
          "", "### 2. Whole organised scans", "",
          "Commands: `%s fill-holes SCAN.pcd -o OUT.pcd --json` and `%s denoise SCAN.pcd -o OUT.pcd --json` "
          "(SCAN converted to binary). For `denoise`, every point it moves along its ray counts as not an input "
          "point, so its free-space column checks the moved points. W×H out: the output header's grid; "
          "(image fill): what the reference fill adds to the whole scan." % (tool, tool), ""] + whole_md + [
          "", "### 3. Denoising roughness on the largest plane", "",
          "The plane: RANSAC on the input (500 tries, `default_rng(0)`, points within 1.5 cm). For each cloud, "
          "its points within 1.5 cm of that plane; 4000 of them (`default_rng(1)`) each get a plane fitted to "
          "their 5 cm neighbourhood (≥ 10 points); the RMS of all those residuals, in mm (−x %%: below the "
          "input's). Commands: `%s denoise SCAN.pcd -o OUT.pcd` (the run of step 2) and "
          "`OMP_NUM_THREADS=2 pcl_mls_smoothing SCAN.pcd MLS.pcd -radius R` (PCL's defaults: order 2)." % tool,
          ""] + rough_md + [
          "", "### 4. Airborne LiDAR tile (terrain_csite3, 377k points, unorganised)", "",
          "8 vertical cylinders of radius %g–%g m per seed punched through (each disc and a 3-s margin fully "
          "sampled, discs 6 s apart). Command: `%s fill-holes holed.pcd -o out.pcd --json` (peak RSS of the "
          "child, `/usr/bin/time -f %%M`). The reference is this script's rasterised harmonic grid fill (cells of 1.5 s, "
          "enclosed empty regions of ≤ 4000 cells, one point per cell; timed in-process). In holes: within "
          "radius + 2 s of a cylinder's axis." % (rmin, rmax, tool), ""] + lidar_md + [""]
    (a.out / "real_scans.md").write_text("\n".join(md))
    print("real_scans.py: wrote %s in %.0f s" % (a.out / "real_scans.md", seconds))


if __name__ == "__main__":
    main()
