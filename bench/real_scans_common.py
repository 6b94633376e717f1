#!/usr/bin/python3
"""What bench/real_scans.py measures with, apart from running the tool: PCD reading and writing (numpy),
the damage (discs punched in image space, cylinders through a LiDAR tile), the scores (coverage,
removed-to-output, free-space violations), the image-space and grid harmonic fills it compares against,
and the plane roughness. Definitions: real_scans.py's docstring. Only numpy and scipy."""
import subprocess
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree

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

def punch_discs(arr, width, height, seed, depth, radius_px, who):
    """8 discs of NaN in image space (numpy default_rng(seed)), radii in radius_px, each with its 2-px
    ring valid and on one surface (`depth` — z, or a range — spread of disc + ring < 3 % of its
    median), disc + ring not touching another's nor leaving the image. -> (holed array, removed
    points, their flat pixel indices, holes as (row, col, radius))."""
    P = xyz(arr)
    valid = finite_rows(P).reshape(height, width)
    rng = np.random.default_rng(seed)
    taken = np.zeros((height, width), bool)
    holes, tries = [], 0
    while len(holes) < HOLES and tries < 20000:
        tries += 1
        r = int(rng.integers(radius_px[0], radius_px[1] + 1))
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
        sys.exit("%s: only %d holes fit on one surface each (seed %d)" % (who, len(holes), seed))
    yy, xx = np.ogrid[:height, :width]
    mask = np.zeros((height, width), bool)
    for cy, cx, r in holes:
        mask |= (yy - cy) ** 2 + (xx - cx) ** 2 <= r * r
    flat = mask.ravel()
    holed = arr.copy()
    for c in "xyz":
        holed[c][flat] = np.nan
    return holed, P[flat], np.flatnonzero(flat), holes


def punch_image(arr, width, height, seed):
    """8 discs of RADIUS_PX in a depth image, on one surface by their depth (punch_discs).
    -> (holed array, removed points, holes as (row, col, radius))."""
    P = xyz(arr)
    valid = finite_rows(P).reshape(height, width)
    depth = np.where(valid, P[:, 2].reshape(height, width), np.nan)
    holed, removed, _, holes = punch_discs(arr, width, height, seed, depth, RADIUS_PX, "real_scans.py")
    return holed, removed, holes


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

def largest_plane(P, threshold=PLANE_THRESHOLD, across=None):
    """RANSAC: 500 tries of 3 points (default_rng(0)), the plane with the most points within `threshold`
    (1.5 cm). With `across` (a unit normal), only planes within 30 degrees of perpendicular to it."""
    rng = np.random.default_rng(0)
    best = (0, None)
    for _ in range(PLANE_TRIES):
        s = P[rng.choice(len(P), 3, replace=False)]
        n = np.cross(s[1] - s[0], s[2] - s[0])
        norm = np.linalg.norm(n)
        if norm == 0:
            continue
        n /= norm
        if across is not None and abs(n @ across) > np.cos(np.radians(60.0)):
            continue
        d = -n @ s[0]
        count = int((np.abs(P @ n + d) < threshold).sum())
        if count > best[0]:
            best = (count, (n, d))
    return best[1]


def local_rms_mm(region, radius=ROUGHNESS_RADIUS, points=ROUGHNESS_POINTS):
    """RMS residual (mm) of the `radius` neighbourhoods (>= 10 points) of `points` seeded points
    (default_rng(1)) of the region, each to its own least-squares plane."""
    if len(region) < 10:
        return float("nan")
    tree = cKDTree(region)
    q = region[np.random.default_rng(1).choice(len(region), min(points, len(region)), replace=False)]
    squares, count = 0.0, 0
    for nb in tree.query_ball_point(q, radius, workers=2):
        if len(nb) < 10:
            continue
        X = region[nb] - region[nb].mean(0)
        squares += np.linalg.eigh(X.T @ X)[0][0]
        count += len(nb)
    return 1000 * float(np.sqrt(squares / max(count, 1)))


def roughness_mm(P, plane):
    """local_rms_mm of the cloud's points within 1.5 cm of the plane (5 cm neighbourhoods of 4000
    seeded points). -> (mm, region points)."""
    n, d = plane
    region = P[np.abs(P @ n + d) < PLANE_THRESHOLD]
    return local_rms_mm(region), len(region)


# ---------------------------------------------------------------- running
