#!/usr/bin/python3
"""Two ways of denoising a relief cloud with patches, measured against the geometric base (issue 37).

usage: /usr/bin/python3 bench/denoise_probes.py {residual,nonlocal} --noisy CASE/cloud_noise_0.5.ply --gt CASE/gt.ply
           --base BASE.ply --base-json BASE.json [--out OUT.ply] [method options]

The inputs are one of the harness's cases (cases.py makes CASE/gt.ply and CASE/cloud_noise_0.5.ply) and the
project's geometric base on it, without patches:
    build/pcl_patchdict denoise CASE/cloud_noise_0.5.ply --no-patches -o BASE.ply --json --quiet > BASE.json
(the report gives "noise_sigma" and "spacing"). Each base point is matched to the noisy point it came from (the
base keeps the input's order and drops the outliers), and a method moves that point along the local normal:
  - residual: K-SVD on the residual of the noisy cloud over the base. One patch per --stride base points, an N x N
    grid of bins of b spacings in the plane of the 16 nearest base points; a Gaussian splat (kern bins) of the
    residual heights gives the patch; a 64-atom dictionary (sklearn's MiniBatchDictionaryLearning on 20000
    patches), OMP with --maxk atoms a patch (0: stop at C x the bin noise), and every point takes the mean of the
    bilinear values of the patches that hold it, added to the base.
  - nonlocal: per base point a descriptor, the N x N splat of the noisy heights over a weighted tangent plane of
    the base, turned by the structure tensor of a quadric fit, in PCA space (dims) with flipped and negated copies;
    the K nearest descriptors weigh exp(-d^2/h^2), h^2 = f x the expected same-patch distance, and the point's new
    height is the weighted mean of those patches' finer height grids (bv spacings) at the point's own position,
    with weight `self` on its own grid. The oracle uses the same matches and weights on the true heights (closest
    points of gt.ply): how far the matching itself could go.
One JSON line: the base's and the method's rms distance to gt.ply (open3d ray casting), their ratio, and for
nonlocal the oracle's ratio and the median effective number of neighbours. On sole at noise 0.5 neither method
reaches 0.85 x the base (residual 0.957, nonlocal 0.865, oracle 0.784).

A measurement probe for issue 37, not part of the library; needs numpy, scipy, scikit-learn and open3d.
"""
import argparse
import json
import time

import numpy as np
import open3d as o3d
from scipy.spatial import cKDTree


def load_points(path):
    return np.asarray(o3d.io.read_point_cloud(path).points, np.float64)


class Truth:
    """Ray-casting scene of the ground-truth mesh."""

    def __init__(self, path):
        mesh = o3d.io.read_triangle_mesh(path)
        self.scene = o3d.t.geometry.RaycastingScene()
        self.scene.add_triangles(np.asarray(mesh.vertices).astype(np.float32),
                                 np.asarray(mesh.triangles).astype(np.uint32))

    def rms(self, P):
        d = self.scene.compute_distance(o3d.core.Tensor(P.astype(np.float32))).numpy()
        return float(np.sqrt(np.mean(d.astype(np.float64) ** 2)))

    def closest(self, P):
        return self.scene.compute_closest_points(o3d.core.Tensor(P.astype(np.float32)))['points'].numpy().astype(
            np.float64)


def match_rows(noisy, base, tol):
    """Row of the noisy point each base point came from: the base keeps the input's order, drops some points and
    moves the rest by less than tol."""
    idx = np.empty(len(base), np.int64)
    j = 0
    for i in range(len(base)):
        while np.sum((noisy[j] - base[i]) ** 2) > tol * tol:
            j += 1
        idx[i] = j
        j += 1
    return idx


def tangent_axes(n):
    ax = np.where(np.abs(n[:, 0:1]) < 0.9, np.array([[1., 0, 0]]), np.array([[0, 1., 0]]))
    t1 = ax - (ax * n).sum(1, keepdims=True) * n
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return t1, np.cross(n, t1)


def splat(u, v, h, mask, centres, kern):
    """Gaussian splat of heights h at bin coordinates (u, v): weight sums W, weighted heights H, sum of squared
    weights W2, each rows x bins x bins."""
    gu = np.exp(-0.5 * ((u[:, :, None] - centres) / kern) ** 2) * mask[:, :, None]
    gv = np.exp(-0.5 * ((v[:, :, None] - centres) / kern) ** 2)
    return (np.einsum('ski,skj->sij', gu, gv), np.einsum('ski,skj,sk->sij', gu, gv, h),
            np.einsum('ski,skj->sij', gu ** 2, gv ** 2))


def bilinear(G, rows, p, q):
    """Values of grids G (rows x n x n) at fractional bin coordinates (p, q) clipped into the grid."""
    n = G.shape[1]
    p = np.clip(p, 0, n - 1 - 1e-9)
    q = np.clip(q, 0, n - 1 - 1e-9)
    i0, j0 = np.floor(p).astype(int), np.floor(q).astype(int)
    i1, j1 = np.minimum(i0 + 1, n - 1), np.minimum(j0 + 1, n - 1)
    fu, fv = p - i0, q - j0
    return (G[rows, i0, j0] * (1 - fu) * (1 - fv) + G[rows, i1, j0] * fu * (1 - fv) + G[rows, i0, j1] * (1 - fu) * fv
            + G[rows, i1, j1] * fu * fv)


def residual_coding(X, B, sig, s, a):
    """K-SVD denoising of the residual X - B along the base normals; returns the corrected base."""
    from sklearn.decomposition import MiniBatchDictionaryLearning
    from sklearn.linear_model import orthogonal_mp_gram
    tree = cKDTree(B)
    _, nn = tree.query(B, 16)
    Q = B[nn] - B[nn].mean(1, keepdims=True)
    normals = np.linalg.eigh(np.einsum('nki,nkj->nij', Q, Q))[1][:, :, 0]
    P, bw = a.N, a.b * s
    half = P * bw / 2
    seeds = np.arange(0, len(B), a.stride)
    nrad = half * np.sqrt(2)
    kq = int(np.ceil(0.25 * (2 * nrad / s) ** 2 * np.pi / 4 * 1.6)) + 8  # enough neighbours to cover the square
    _, nb = tree.query(B[seeds], kq)
    n = normals[seeds]
    t1, t2 = tangent_axes(n)
    D = B[nb] - B[seeds][:, None, :]
    u = (D * t1[:, None, :]).sum(2) / bw + P / 2
    v = (D * t2[:, None, :]).sum(2) / bw + P / 2
    h = ((X[nb] - B[nb]) * n[:, None, :]).sum(2)
    inside = (u >= 0) & (u < P) & (v >= 0) & (v < P)
    W, H, W2 = splat(u, v, h, inside, np.arange(P) + 0.5, a.kern)
    Y = (H / np.maximum(W, 1e-12)).reshape(len(seeds), -1)
    sig_bin = sig * np.sqrt(np.median((W2 / np.maximum(W, 1e-12) ** 2)))  # noise of a bin value
    rng = np.random.default_rng(0)
    sub = rng.choice(len(Y), min(20000, len(Y)), replace=False)
    dl = MiniBatchDictionaryLearning(n_components=a.atoms, alpha=1.0, batch_size=256, max_iter=20, random_state=0,
                                     fit_algorithm='cd', transform_algorithm='omp')
    atoms = dl.fit(Y[sub]).components_
    atoms /= np.linalg.norm(atoms, axis=1, keepdims=True)
    G, Xy = atoms @ atoms.T, atoms @ Y.T
    if a.maxk > 0:
        coef = orthogonal_mp_gram(G, Xy, n_nonzero_coefs=a.maxk)
    else:
        coef = orthogonal_mp_gram(G, Xy, tol=P * P * (a.C * sig_bin) ** 2, norms_squared=(Y ** 2).sum(1))
    grids = (atoms.T @ coef).T.reshape(-1, P, P)
    val = bilinear(grids, np.arange(len(seeds))[:, None], u - 0.5, v - 0.5)
    corr, cnt = np.zeros_like(B), np.zeros(len(B))
    np.add.at(corr, nb.ravel(), (val[:, :, None] * n[:, None, :] * inside[:, :, None]).reshape(-1, 3))
    np.add.at(cnt, nb.ravel(), inside.ravel().astype(float))
    info = {'patches': len(seeds), 'mean_atoms': float((coef != 0).sum(0).mean())}
    return B + corr / np.maximum(cnt, 1)[:, None], info


def describe(B, X, S, s, a):
    """Per base point: frame (centre c, normal n), descriptor (N x N splat of the chosen heights), finer height
    grids of the noisy (GX) and true (GT) points, the point's own position in its fine grid (UV), its noisy and
    base heights, and the noise factor of each descriptor bin."""
    m, N, bw = len(B), a.N, a.b * s
    R = N * bw / 2 * np.sqrt(2)  # half-diagonal of the patch
    Nv, bvv = int(round(N * a.b / a.bv)), a.bv * s
    cx, cv = np.arange(N) + 0.5 - N / 2, np.arange(Nv)
    r = dict(desc=np.zeros((m, N * N)), GX=np.zeros((m, Nv * Nv)), GT=np.zeros((m, Nv * Nv)), UV=np.zeros((m, 2)),
             hval=np.zeros(m), hb=np.zeros(m), Nrm=np.zeros((m, 3)), varb=np.zeros((m, N * N)))
    tree = cKDTree(B)
    for c0 in range(0, m, 4000):
        I = np.arange(c0, min(m, c0 + 4000))
        nb = tree.query_ball_point(B[I], R)
        NB = np.full((len(I), max(len(x) for x in nb)), -1)
        for row, x in enumerate(nb):
            NB[row, :len(x)] = x
        msk = NB >= 0
        NBc = np.where(msk, NB, 0)
        P, Px = B[NBc], X[NBc]
        w = np.exp(-0.5 * ((P - B[I][:, None]) ** 2).sum(2) / (R / 2) ** 2) * msk
        c = (w[:, :, None] * P).sum(1) / w.sum(1, keepdims=True)
        Q = (P - c[:, None]) * np.sqrt(w)[:, :, None]
        n = np.linalg.eigh(np.einsum('nki,nkj->nij', Q, Q))[1][:, :, 0]
        t1, t2 = tangent_axes(n)
        D = P - c[:, None]
        u, v, hB = (D * t1[:, None]).sum(2), (D * t2[:, None]).sum(2), (D * n[:, None]).sum(2)
        hX = ((Px - c[:, None]) * n[:, None]).sum(2)
        ca, sa = np.ones((len(I), 1)), np.zeros((len(I), 1))
        if a.rot == 'tensor':  # weighted quadric fit of the base heights; structure tensor of its gradient
            A = np.stack([u * u, u * v, v * v, u, v, np.ones_like(u)], 2) / np.array([R * R, R * R, R * R, R, R, 1])
            Aw = A * w[:, :, None]
            co = np.linalg.solve(np.einsum('nki,nkj->nij', Aw, A) + 1e-9 * np.eye(6), np.einsum('nki,nk->ni', Aw, hB))
            qa, qb, qc, qd, qe = co[:, 0] / R ** 2, co[:, 1] / R ** 2, co[:, 2] / R ** 2, co[:, 3] / R, co[:, 4] / R
            gu = 2 * qa[:, None] * u + qb[:, None] * v + qd[:, None]
            gv = qb[:, None] * u + 2 * qc[:, None] * v + qe[:, None]
            J = np.stack([(w * gu * gu).sum(1), (w * gu * gv).sum(1), (w * gv * gv).sum(1)], 1)
            ang = 0.5 * np.arctan2(2 * J[:, 1], J[:, 0] - J[:, 2])
            ca, sa = np.cos(ang)[:, None], np.sin(ang)[:, None]
            u, v = ca * u + sa * v, -sa * u + ca * v
        W, H, W2 = splat(u / bw, v / bw, hX if a.desc == 'noisy' else hB, msk, cx, a.kern)
        W, H, W2 = W.reshape(len(I), -1), H.reshape(len(I), -1), W2.reshape(len(I), -1)
        fill = (w * hB).sum(1, keepdims=True) / w.sum(1, keepdims=True)  # empty bins: mean base height
        ok = W > 0.3
        r['desc'][I] = np.where(ok, H / np.maximum(W, 1e-12), fill)
        r['varb'][I] = np.where(ok, W2 / np.maximum(W, 1e-12) ** 2, 0)

        def fine(Pts):
            Dd = Pts - c[:, None]
            uu, vv = (Dd * t1[:, None]).sum(2), (Dd * t2[:, None]).sum(2)
            return ((ca * uu + sa * vv) / bvv + Nv / 2 - 0.5, (-sa * uu + ca * vv) / bvv + Nv / 2 - 0.5,
                    (Dd * n[:, None]).sum(2))
        for Pts, key in ((Px, 'GX'), (S[NBc], 'GT')):
            pu, pv, ph = fine(Pts)
            Wv, Hv, _ = splat(pu, pv, ph, msk, cv, a.kv)
            Wv, Hv = Wv.reshape(len(I), -1), Hv.reshape(len(I), -1)
            r[key][I] = np.where(Wv > 0.05, Hv / np.maximum(Wv, 1e-12), np.nan)
        pu, pv, _ = fine(X[I][:, None])
        r['UV'][I] = np.c_[pu[:, 0], pv[:, 0]]
        r['hval'][I], r['hb'][I], r['Nrm'][I] = ((X[I] - c) * n).sum(1), ((B[I] - c) * n).sum(1), n
    return r


def nonlocal_averaging(X, B, S, sig, s, a, truth):
    """Non-local means of patch heights; returns the output cloud, the oracle's and the median effective
    number of neighbours."""
    r = describe(B, X, S, s, a)
    m, N, nc = len(B), a.N, a.copies
    Nv = int(round(N * a.b / a.bv))
    # noise variance of a descriptor bin: sig^2 * sum w^2 / (sum w)^2
    if a.desc == 'noisy':
        sb2 = sig ** 2 * np.mean(r['varb'])
    else:  # base heights: crude estimate from the base's own error
        sb2 = truth.rms(B) ** 2 * np.mean(r['varb'])

    def copies(Dm):  # identity, 180-degree turn, and the two mirror images with negated heights
        g = Dm.reshape(-1, N, N)
        out = [g, g[:, ::-1, ::-1], -g[:, :, ::-1], -g[:, ::-1, :]]
        return [o.reshape(len(Dm), -1) for o in out[:nc]]
    sub = np.random.default_rng(0).choice(m, min(20000, m), replace=False)
    Sall = np.concatenate(copies(r['desc'][sub]), 0)  # PCA on all copies so the basis is symmetric
    Vd = np.linalg.svd(Sall - Sall.mean(0), full_matrices=False)[2][:a.dims].T
    mu = Sall.mean(0)
    emb = [(cp - mu) @ Vd for cp in copies(r['desc'])]
    sgn = np.array([1, 1, -1, -1][:nc], float)
    SRC, CP = np.tile(np.arange(m), nc), np.repeat(np.arange(nc), m)
    dd, ii = cKDTree(np.concatenate(emb, 0)).query(emb[0], a.K + nc, workers=2, eps=a.eps)
    notself = SRC[ii] != np.arange(m)[:, None]

    def grid_at(G, src, cp, p, q):  # copy cp of grid src at bin coordinates (p, q) of the query's frame
        flipP, flipQ = (cp == 1) | (cp == 3), (cp == 1) | (cp == 2)
        p, q = np.where(flipP, Nv - 1 - p, p), np.where(flipQ, Nv - 1 - q, q)
        return np.where(cp >= 2, -1.0, 1.0) * bilinear(G.reshape(-1, Nv, Nv), src, p, q)
    if a.val == 'grid':
        P_, Q_ = np.repeat(r['UV'][:, 0:1], ii.shape[1], 1), np.repeat(r['UV'][:, 1:2], ii.shape[1], 1)
        Vn, Vt = grid_at(r['GX'], SRC[ii], CP[ii], P_, Q_), grid_at(r['GT'], SRC[ii], CP[ii], P_, Q_)
        selfv = grid_at(r['GX'], np.arange(m), np.zeros(m, int), r['UV'][:, 0], r['UV'][:, 1])
        selfv = np.where(np.isfinite(selfv), selfv, r['hb'])
    else:  # the point heights of the matched patches' centres
        htrue = ((S - B) * r['Nrm']).sum(1) + r['hb']
        Vn = (sgn[:, None] * (r['hval'] if a.val == 'noisy' else r['hb'])).ravel()[ii]
        Vt = (sgn[:, None] * htrue).ravel()[ii]
        selfv = r['hval']
    fin = np.isfinite(Vn) & np.isfinite(Vt)
    Vn, Vt = np.where(fin, Vn, 0), np.where(fin, Vt, 0)
    wg = np.exp(-dd ** 2 / (a.f * 2 * a.dims * sb2)) * (notself & fin)
    dn = wg.sum(1) + a.self
    outs = []
    for V in (Vn, Vt):
        e = ((wg * V).sum(1) + a.self * selfv) / np.maximum(dn, 1e-12)
        e = np.where(dn > 1e-9, e, r['hb'])
        outs.append(X + (e - r['hval'])[:, None] * r['Nrm'])
    keff = wg.sum(1) ** 2 / np.maximum((wg ** 2).sum(1), 1e-30)
    return outs[0], outs[1], float(np.median(keff))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('method', choices=['residual', 'nonlocal'])
    ap.add_argument('--noisy', required=True, help='CASE/cloud_noise_K.ply')
    ap.add_argument('--gt', required=True, help='CASE/gt.ply')
    ap.add_argument('--base', required=True, help='output of denoise --no-patches on --noisy')
    ap.add_argument('--base-json', required=True, help='its --json report (noise_sigma, spacing)')
    ap.add_argument('--out', default='', help='write the method\'s cloud here')
    ap.add_argument('--N', type=int, default=8, help='bins per patch side')
    ap.add_argument('--b', type=float, default=1.5, help='bin size in spacings')
    ap.add_argument('--kern', type=float, default=0.6, help='splat kernel in bins')
    g = ap.add_argument_group('residual')
    g.add_argument('--atoms', type=int, default=64, help='dictionary atoms')
    g.add_argument('--maxk', type=int, default=4, help='atoms a patch (0: stop at C x the bin noise)')
    g.add_argument('--C', type=float, default=1.15, help='OMP tolerance factor when --maxk 0')
    g.add_argument('--stride', type=int, default=2, help='one patch every stride base points')
    g = ap.add_argument_group('nonlocal')
    g.add_argument('--desc', choices=['noisy', 'base'], default='noisy', help='heights of the descriptor')
    g.add_argument('--val', choices=['grid', 'noisy', 'base'], default='grid',
                   help='averaged values: fine grids at the point, or the centres\' point heights')
    g.add_argument('--dims', type=int, default=12, help='PCA dimensions of the descriptor')
    g.add_argument('--K', type=int, default=64, help='nearest descriptors (plus copies)')
    g.add_argument('--f', type=float, default=3.0, help='h^2 = f x expected same-patch squared distance')
    g.add_argument('--self', type=float, default=1.0, help='weight of the point\'s own grid')
    g.add_argument('--rot', choices=['tensor', 'none'], default='tensor', help='frame rotation')
    g.add_argument('--copies', type=int, choices=[1, 2, 3, 4], default=4, help='flipped/negated copies')
    g.add_argument('--bv', type=float, default=0.75, help='fine grid bin in spacings')
    g.add_argument('--kv', type=float, default=0.5, help='fine grid splat kernel in bins')
    g.add_argument('--eps', type=float, default=0.5, help='approximate nearest-neighbour tolerance')
    a = ap.parse_args()

    t0 = time.time()
    report = json.load(open(a.base_json))
    sig, s = report['noise_sigma'], report['spacing']
    noisy, B = load_points(a.noisy), load_points(a.base)
    truth = Truth(a.gt)
    X = noisy[match_rows(noisy, B, 8 * sig)]
    rb = truth.rms(B)
    row = {'method': a.method, 'noisy': a.noisy}
    if a.method == 'residual':
        out, info = residual_coding(X, B, sig, s, a)
        ro = truth.rms(out)
    else:
        out, oracle, keff = nonlocal_averaging(X, B, truth.closest(X), sig, s, a, truth)
        ro = truth.rms(out)
        info = {'oracle_ratio': round(truth.rms(oracle) / rb, 3), 'keff_median': round(keff, 1)}
    row.update(base_rms=float('%.4g' % rb), rms=float('%.4g' % ro), ratio=round(ro / rb, 3), **info)
    row['seconds'] = round(time.time() - t0, 1)
    own = ('atoms', 'maxk', 'C', 'stride') if a.method == 'residual' else (
        'desc', 'val', 'dims', 'K', 'f', 'self', 'rot', 'copies', 'bv', 'kv', 'eps')
    row['args'] = {k: getattr(a, k) for k in ('N', 'b', 'kern') + own}
    print(json.dumps(row))
    if a.out:
        o3d.io.write_point_cloud(a.out, o3d.geometry.PointCloud(o3d.utility.Vector3dVector(out)))


if __name__ == '__main__':
    main()
