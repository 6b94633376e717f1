#!/usr/bin/python3
"""Before/after pictures of point clouds: a thin slab through each cloud, seen side-on.

usage: cloud_pictures.py OUT.png --slab AXIS=VALUE[,HALF_WIDTH] [--window U0,U1,V0,V1] TITLE=CLOUD.ply ...

Each CLOUD (a face-less PLY: x y z first, float32/float64, as pcl_patchdict writes) becomes one
panel: its points with |AXIS − VALUE| < HALF_WIDTH (default 0.004), projected onto the two other
axes. A name starting with '+' (e.g. +NEW=added.ply) is drawn in orange over the previous panel.
Needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib).
"""
import struct
import sys

import numpy as np
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402


def read_ply_points(path):
    with open(path, 'rb') as f:
        header = []
        while True:
            line = f.readline().decode('ascii', 'replace').strip()
            header.append(line)
            if line == 'end_header':
                break
        fmt = next(h.split()[1] for h in header if h.startswith('format'))
        n = 0
        props = []
        in_vertex = False
        for h in header:
            w = h.split()
            if w[:2] == ['element', 'vertex']:
                n, in_vertex = int(w[2]), True
            elif w[:1] == ['element']:
                in_vertex = False
            elif w[:1] == ['property'] and in_vertex:
                props.append((w[2], {'float': 'f4', 'float32': 'f4', 'double': 'f8', 'float64': 'f8',
                                     'uchar': 'u1', 'uint8': 'u1', 'int': 'i4', 'uint': 'u4'}[w[1]]))
        if fmt == 'ascii':
            data = np.loadtxt(f, max_rows=n, usecols=(0, 1, 2))
            return data.reshape(-1, 3)
        order = '<' if fmt == 'binary_little_endian' else '>'
        dt = np.dtype([(name, order + t) for name, t in props])
        arr = np.frombuffer(f.read(n * dt.itemsize), dt, n)
        return np.stack([arr['x'], arr['y'], arr['z']], 1).astype(float)


def main(argv):
    if len(argv) < 4 or '--slab' not in argv:
        print(__doc__)
        return 2
    out = argv[1]
    slab = argv[argv.index('--slab') + 1]
    axis_name, rest = slab.split('=')
    values = [float(v) for v in rest.split(',')]
    value, half = values[0], (values[1] if len(values) > 1 else 0.004)
    axis = 'xyz'.index(axis_name)
    others = [a for a in range(3) if a != axis]
    window = None
    if '--window' in argv:
        window = [float(v) for v in argv[argv.index('--window') + 1].split(',')]
    panels = []
    skip = {argv.index('--slab'), argv.index('--slab') + 1}
    if '--window' in argv:
        skip |= {argv.index('--window'), argv.index('--window') + 1}
    for i, item in enumerate(argv[2:], 2):
        if i in skip:
            continue
        title, path = item.rsplit('=', 1)
        P = read_ply_points(path)
        P = P[np.abs(P[:, axis] - value) < half]
        if title.startswith('+') and panels:
            panels[-1][2].append((title[1:], P))
        else:
            panels.append((title, P, []))
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4.5), squeeze=False)
    for ax, (title, P, overlays) in zip(axes[0], panels):
        ax.scatter(P[:, others[0]], P[:, others[1]], s=3, c='#335', linewidths=0)
        for name, Q in overlays:
            ax.scatter(Q[:, others[0]], Q[:, others[1]], s=4, c='#e80', linewidths=0, label=name)
        if overlays:
            ax.legend(loc='lower right', fontsize=8, markerscale=5)
        ax.set_title(title, fontsize=10)
        ax.set_aspect('equal')
        if window:
            ax.set_xlim(window[0], window[1])
            ax.set_ylim(window[2], window[3])
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout(pad=1.5)
    fig.savefig(out, dpi=110)
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
