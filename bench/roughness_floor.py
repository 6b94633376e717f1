#!/usr/bin/python3
"""How far the plane-roughness score of a real scan can drop without flattening objects.

The score (real_scans.py's roughness_mm, the same as the harness's plane_roughness.py) takes every
point within 1.5 cm of the largest plane, and on a table-top scan that band takes in the lowest
1.5 cm of the objects standing on the table.  A 5 cm neighbourhood that holds some of a wall keeps
that wall's plane residual however well the noise is removed.  This script splits the score's own
neighbourhoods (same query points as the score, the input's region) into
  - object neighbourhoods: more than --fraction of their points stand more than --rise above the
    table plane (refitted by least squares on the points within 4 mm of the band's median height);
  - table-only neighbourhoods: the rest;
and prints a floor: the score if every table-only neighbourhood became perfectly flat and every
object neighbourhood lost as much residual per point as the table-only ones carry at the same depth
(10 cm bins).  Outputs given after the scan are scored on the same neighbourhoods (pixel by pixel
for organised outputs of the scan's size, by the same query points otherwise).

  roughness_floor.py SCAN.pcd [OUT.pcd ...] [--rise 0.004] [--fraction 0.01]
"""
import argparse
import sys
import tempfile

import numpy as np
from scipy.spatial import cKDTree

from real_scans_common import (PLANE_THRESHOLD, ROUGHNESS_POINTS, ROUGHNESS_RADIUS, finite_rows, largest_plane,
                               read_pcd, xyz)


def table_heights(P, region_rows):
    """Signed heights above the table plane, refitted on the band's points near its median height;
    the sign makes the objects positive."""
    rows, n0 = region_rows, None
    for _ in range(3):
        Y = P[rows]
        c = Y.mean(0)
        V = np.linalg.eigh((Y - c).T @ (Y - c))[1]
        n = V[:, 0] if n0 is None or V[:, 0] @ n0 >= 0 else -V[:, 0]
        n0 = n
        h = (P - c) @ n
        med = np.median(h[region_rows])
        rows = region_rows[np.abs(h[region_rows] - med) < 0.004]
    up = h[region_rows]
    return h if (up > 0.004).sum() >= (up < -0.004).sum() else -h


def neighbourhood_squares(P, neighbourhoods):
    """Smallest eigenvalue of each neighbourhood's scatter (its plane residual), and its size."""
    W, C = np.zeros(len(neighbourhoods)), np.zeros(len(neighbourhoods))
    for k, rows in enumerate(neighbourhoods):
        Y = P[rows]
        Y = Y[finite_rows(Y)]
        if len(Y) < 10:
            continue
        X = Y - Y.mean(0)
        W[k], C[k] = np.linalg.eigh(X.T @ X)[0][0], len(Y)
    return W, C


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("clouds", nargs="+")
    p.add_argument("--rise", type=float, default=0.004, help="height above the table that marks an object (m)")
    p.add_argument("--fraction", type=float, default=0.01, help="share of object points that marks a neighbourhood")
    a = p.parse_args()
    work = tempfile.mkdtemp(prefix="roughness_floor_")
    arr, _ = read_pcd(a.clouds[0], work)
    P = xyz(arr)
    finite = finite_rows(P)
    n, d = largest_plane(P[finite])
    band = np.nonzero(finite & (np.abs(P @ n + d) < PLANE_THRESHOLD))[0]
    h = table_heights(P, band)
    region = P[band]
    pick = np.random.default_rng(1).choice(len(region), min(ROUGHNESS_POINTS, len(region)), replace=False)
    queries = region[pick]
    local = cKDTree(region).query_ball_point(queries, ROUGHNESS_RADIUS, workers=2)
    neighbourhoods = [band[np.asarray(nb, dtype=np.int64)] for nb in local]
    W, C = neighbourhood_squares(P, neighbourhoods)
    obj = np.array([(h[rows] > a.rise).mean() > a.fraction if len(rows) else False for rows in neighbourhoods])
    rms = lambda W_, C_, m: 1000 * np.sqrt(W_[m].sum() / max(C_[m].sum(), 1))
    total = rms(W, C, C > 0)
    bins = np.floor(queries[:, 2] / 0.1)
    geometry = 0.0
    for b in np.unique(bins[obj]):
        table = (bins == b) & ~obj & (C > 0)
        if table.sum() < 20:
            table = ~obj & (C > 0) & (np.abs(queries[:, 2] - (b + 0.5) * 0.1) < 0.15)
        per_point = W[table].sum() / C[table].sum()
        here = (bins == b) & obj
        geometry += np.maximum(W[here] - C[here] * per_point, 0).sum()
    floor = 1000 * np.sqrt(geometry / C.sum())
    print("%s: score %.3f mm; object neighbourhoods %d of %d (%.1f %% of points) %.3f, table-only %.3f" % (
        a.clouds[0], total, obj.sum(), len(obj), 100 * C[obj].sum() / C.sum(), rms(W, C, obj), rms(W, C, ~obj)))
    print("  floor %.3f mm = %.1f %% below the input (object part alone %.3f)" % (
        floor, 100 * (1 - floor / total), 1000 * np.sqrt(geometry / max(C[obj].sum(), 1))))
    for path in a.clouds[1:]:
        out, _ = read_pcd(path, work)
        Q = xyz(out)
        if len(Q) == len(P):
            Wo, Co = neighbourhood_squares(Q, neighbourhoods)
        else:
            Q = Q[finite_rows(Q)]
            own = Q[np.abs(Q @ n + d) < PLANE_THRESHOLD]
            hoods = cKDTree(own).query_ball_point(queries, ROUGHNESS_RADIUS, workers=2)
            Wo, Co = neighbourhood_squares(own, [np.asarray(nb, dtype=np.int64) for nb in hoods])
        print("  %s: %.3f mm (%.1f %% below the input); object %.3f, table-only %.3f" % (
            path, rms(Wo, Co, Co > 0), 100 * (1 - rms(Wo, Co, Co > 0) / total), rms(Wo, Co, obj), rms(Wo, Co, ~obj)))


if __name__ == "__main__":
    sys.exit(main())
