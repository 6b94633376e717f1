#!/usr/bin/python3
"""What bench/spinning_scans.py measures with on spinning-LiDAR frames (organised: rows = beams, columns =
azimuth steps that wrap around, sensor at the origin), apart from running the tool and what it takes from
real_scans_common.py (PCD I/O, spacing, added points, the hole scores): the discs punched in the range
image, the harmonic range-image fill it compares against, the beam grid (a point's pixel is the measured
beam nearest its direction), the spinning sensor's free-space test, and the plane roughness of the ground
and of the largest wall with LiDAR-sized thresholds. Definitions: spinning_scans.py's docstring.
Only numpy and scipy."""
import sys

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree

from real_scans_common import (xyz, finite_rows, spacing_at, split_added, score, punch_discs,  # noqa: E402
                               largest_plane, local_rms_mm as common_local_rms_mm)

HOLES, SPREAD, MAX_FILL_PX = 8, 0.03, 2000
PLANE_THRESHOLD, ROUGHNESS_RADIUS, ROUGHNESS_POINTS, WALL_ABOVE = 0.1, 0.5, 4000, 0.5


def radius_px(height):
    """Disc radii in pixels: 2-4 on 32-beam frames, 3-8 on 128-beam ones (the harness's --radius-px)."""
    return (2, 4) if height <= 64 else (3, 8)


def range_image(P, width, height):
    """Range of each pixel (NaN without a return), as a height x width image."""
    ok = finite_rows(P)
    return np.where(ok, np.linalg.norm(np.nan_to_num(P), axis=1), np.nan).reshape(height, width)


# ---------------------------------------------------------------- punched holes

def punch_range_image(arr, width, height, seed):
    """8 discs of NaN in the range image (numpy default_rng(seed)): each centred on a valid pixel, the disc
    and its 2-px ring valid and on one surface (range spread < 3 % of the median), disc + ring not touching
    another's nor leaving the image (so the disc keeps off the first and last 2 beams; no wrap).
    -> (holed array, removed points, their flat pixel indices, holes as (row, col, radius))."""
    return punch_discs(arr, width, height, seed, range_image(xyz(arr), width, height), radius_px(height),
                       "spinning_scans.py")


# ---------------------------------------------------------------- the harmonic range-image fill

def wrapped_labels(empty):
    """4-connected regions of `empty` with the azimuth wrapping (column W-1 next to column 0).
    -> (labels, -1 off the regions, 0..n-1 on them; n)."""
    lab, n = ndimage.label(empty)
    seam = (lab[:, -1] > 0) & (lab[:, 0] > 0)
    graph = sparse.coo_matrix((np.ones(int(seam.sum())), (lab[seam, -1], lab[seam, 0])), shape=(n + 1, n + 1))
    _, comp = connected_components(graph, directed=False)
    _, merged = np.unique(comp[1:], return_inverse=True)  # region ids 0..m-1 for the labels 1..n
    out = np.full(lab.shape, -1, np.int64)
    out[lab > 0] = merged[lab[lab > 0] - 1]
    return out, int(merged.max()) + 1 if n else 0


def neighbours(height, width):
    """The 4-neighbour shifts of every pixel: rows clipped (a border pixel is its own neighbour, which
    the callers never reach), columns wrapped. -> list of flat index arrays."""
    rows, cols = np.divmod(np.arange(height * width), width)
    return [np.clip(rows + dr, 0, height - 1) * width + (cols + dc) % width
            for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1))]


def fill_regions(valid, rng_img, max_px=MAX_FILL_PX):
    """The NaN regions to fill: enclosed (wrapped 4-connected), at most max_px pixels, not touching the
    first or last beam, their rim (valid 4-neighbours) spread in range <= 3 % of its median. -> mask."""
    height, width = valid.shape
    labels, n = wrapped_labels(~valid)
    if n == 0:
        return np.zeros_like(valid)
    flat = labels.ravel()
    sizes = np.bincount(flat[flat >= 0], minlength=n)
    ok = sizes <= max_px
    ok[np.unique(labels[0][labels[0] >= 0])] = False
    ok[np.unique(labels[-1][labels[-1] >= 0])] = False
    # rim pixels: (region, valid pixel) pairs over the 4 neighbours, each pixel once per region
    pairs = [np.stack([flat[nb], np.arange(len(flat))], 1)[(flat[nb] >= 0) & valid.ravel()]
             for nb in neighbours(height, width)]
    pairs = np.unique(np.concatenate(pairs), axis=0)
    r = rng_img.ravel()[pairs[:, 1]]
    starts = np.searchsorted(pairs[:, 0], np.arange(n + 1))
    for k in np.flatnonzero(ok):
        d = r[starts[k]:starts[k + 1]]
        if len(d) == 0 or d.max() - d.min() > SPREAD * np.median(d):
            ok[k] = False
    return ((flat >= 0) & ok[np.maximum(flat, 0)]).reshape(height, width)


def harmonic_solve_wrapped(fill, values):
    """Laplace's equation on the True pixels of `fill` (none on the first or last row), columns wrapping,
    for each channel of values (H x W x k): 4 u_i - unknown neighbours = known neighbours.
    -> (flat indices, n x k solution)."""
    height, width = fill.shape
    f = fill.ravel()
    idx = np.flatnonzero(f)
    ids = np.full(f.size, -1, np.int64)
    ids[idx] = np.arange(len(idx))
    V = values.reshape(f.size, -1)
    rows, cols, vals = [np.arange(len(idx))], [np.arange(len(idx))], [np.full(len(idx), 4.0)]
    b = np.zeros((len(idx), V.shape[1]))
    for nb in neighbours(height, width):
        nb = nb[idx]
        unknown = f[nb]
        rows.append(np.flatnonzero(unknown))
        cols.append(ids[nb[unknown]])
        vals.append(np.full(int(unknown.sum()), -1.0))
        b += np.where(unknown[:, None], 0.0, V[nb])
    if len(idx) == 0:
        return idx, np.zeros((0, V.shape[1]))
    A = sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(len(idx), len(idx)))
    x = spsolve(A, b)
    return idx, x.reshape(len(idx), -1)


def range_image_fill(arr, width, height):
    """Harmonic range-image fill: range and unit beam direction interpolated harmonically over each
    region of fill_regions; the new point is the normalised direction times the range."""
    P = xyz(arr)
    valid = finite_rows(P).reshape(height, width)
    rng_img = range_image(P, width, height)
    R = np.nan_to_num(rng_img).ravel()
    U = np.where(valid.ravel()[:, None], np.nan_to_num(P) / np.maximum(R, 1e-12)[:, None], 0.0)
    idx, x = harmonic_solve_wrapped(fill_regions(valid, rng_img), np.column_stack([R, U]))
    out = arr.copy()
    if len(idx):
        pts = x[:, 1:] / np.linalg.norm(x[:, 1:], axis=1)[:, None] * x[:, :1]
        out["x"][idx], out["y"][idx], out["z"][idx] = pts[:, 0], pts[:, 1], pts[:, 2]
    return out


# ---------------------------------------------------------------- the spinning sensor model

class BeamGrid:
    """The measured beam directions of a frame (plus, for a holed frame, the removed pixels' directions,
    which the sensor knows too): maps a point to the pixel whose beam direction is nearest its direction
    from the origin; `near` when within 1.5 angular steps (the median nearest-direction distance)."""

    def __init__(self, P_full, width, extra=None):
        ok = finite_rows(P_full)
        idx = np.flatnonzero(ok)
        D = P_full[ok] / np.linalg.norm(P_full[ok], axis=1)[:, None]
        if extra is not None:
            e_idx, e_P = extra
            idx = np.concatenate([idx, e_idx])
            D = np.vstack([D, e_P / np.linalg.norm(e_P, axis=1)[:, None]])
        self.idx, self.tree, self.width = idx, cKDTree(D), width
        nn, _ = self.tree.query(D[::max(1, len(D) // 20000)], 2, workers=2)
        self.step = float(np.median(nn[:, 1]))

    def pixel(self, Q):
        """-> (row, col, near) of the beam nearest each point's direction."""
        U = Q / np.maximum(np.linalg.norm(Q, axis=1), 1e-12)[:, None]
        d, j = self.tree.query(U, workers=2)
        row, col = np.divmod(self.idx[j], self.width)
        return row, col, d <= 1.5 * self.step


def free_space_spinning(P_in, width, height, added, grid, tree_in):
    """Added points nearer the origin than the minimum measured range of the 3 x 3 beams around their
    nearest beam by more than max(3 s, 1 % of that range): space the beams crossed. Azimuth wraps; beams
    do not; only points whose direction is near a measured beam count."""
    if len(added) == 0:
        return 0
    rng_img = np.nan_to_num(range_image(P_in, width, height), nan=np.inf)
    pad = np.pad(rng_img, 1, mode="wrap")
    pad[0, :] = pad[-1, :] = np.inf
    nearest = np.min([pad[1 + dy:1 + dy + height, 1 + dx:1 + dx + width] for dy in (-1, 0, 1) for dx in (-1, 0, 1)],
                     axis=0)
    row, col, near = grid.pixel(added)
    seen = nearest[row, col]
    s = spacing_at(tree_in, added)
    tol = np.maximum(3 * s, 0.01 * np.where(np.isfinite(seen), seen, 0))
    with np.errstate(invalid="ignore"):
        return int((near & np.isfinite(seen) & (np.linalg.norm(added, axis=1) < seen - tol)).sum())


def score_holes(holed, width, height, removed, removed_pixels, holes, P_out):
    """real_scans_common.score with the spinning sensor's rules: in a hole = the nearest beam (of the
    holed frame's measured directions and the removed pixels') near and within radius + 1.5 px of a
    disc's centre; free space by free_space_spinning."""
    P_in = xyz(holed)
    grid = BeamGrid(P_in, width, extra=(removed_pixels, removed))

    def in_holes(added):
        row, col, near = grid.pixel(added)
        return near & np.any([(row - cy) ** 2 + (col - cx) ** 2 <= (r + 1.5) ** 2 for cy, cx, r in holes], axis=0)

    result = score(P_in, width, height, removed, P_out, in_holes)
    _, tree, _, added = split_added(P_in, P_out)
    result["free_space_violations"] = free_space_spinning(P_in, width, height, added, grid, tree)
    return result


def whole_frame_check(P_in, width, height, P_out):
    """A whole frame: output points that are not input points (moved ones count) and their free-space
    violations against the frame's own beams. -> (not-input points, violations)."""
    _, tree, _, added = split_added(P_in, P_out)
    return len(added), free_space_spinning(P_in, width, height, added, BeamGrid(P_in, width), tree)


# ---------------------------------------------------------------- plane roughness

def ransac_plane(P, across=None):
    """real_scans_common.largest_plane at the LiDAR's threshold (0.1 m), the normal oriented so that the
    sensor (the origin) lies on its positive side."""
    n, d = largest_plane(P, PLANE_THRESHOLD, across)
    return (n, d) if d >= 0 else (-n, -d)


def ground_and_wall(P):
    """The ground: the largest plane of the input's finite points; the wall: the largest plane among the
    points more than 0.5 m above the ground (on the sensor's side) within 30 degrees of perpendicular to
    the ground (without that, a frame's largest plane up there can be car roofs)."""
    ground = ransac_plane(P)
    n, d = ground
    return ground, ransac_plane(P[P @ n + d > WALL_ABOVE], across=n)


def plane_points(P, plane, ground=None):
    """The points within the threshold of `plane`; with `ground`, only those more than 0.5 m above it."""
    n, d = plane
    keep = np.abs(P @ n + d) < PLANE_THRESHOLD
    if ground is not None:
        keep &= P @ ground[0] + ground[1] > WALL_ABOVE
    return P[keep]


def local_rms_mm(region):
    """real_scans_common.local_rms_mm with a LiDAR-sized neighbourhood (0.5 m)."""
    return common_local_rms_mm(region, ROUGHNESS_RADIUS, ROUGHNESS_POINTS)


def tilt_degrees(plane):
    """Angle of a plane's normal to the vertical (z) axis: ~0 for the ground, ~90 for a wall."""
    return float(np.degrees(np.arccos(min(1.0, abs(plane[0][2])))))
