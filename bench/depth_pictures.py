#!/usr/bin/python3
"""Pictures of organised clouds (numpy only; PNG written with zlib):

  depth_pictures.py fill IN.pcd OUT.pcd PICTURE.png
      the output's depth image, shaded (grey; black: no depth), its filled pixels (NaN in IN,
      finite in OUT) shaded in orange
  depth_pictures.py edge IN.pcd OUT.pcd PICTURE.png --rows R0:R1 --cols C0:C1
      a view from above of the pixels in that window (x across, depth z down), before (left) and
      after (right): the thickness of a surface seen edge-on is its noise

PCDs in binary or ascii, or binary_compressed via `pcl_convert_pcd_ascii_binary` (pcl-tools)."""
import argparse
import struct
import sys
import tempfile
import zlib

import numpy as np

import real_scans_common


def read_pcd(path):
    """-> (x, y, z as float64 arrays, width, height), through real_scans_common.py's reader."""
    with tempfile.TemporaryDirectory() as tmp:
        arr, info = real_scans_common.read_pcd(path, tmp)
    P = real_scans_common.xyz(arr)
    return P[:, 0], P[:, 1], P[:, 2], info['width'], info['height']


def write_png(path, rgb):
    h, w, _ = rgb.shape
    rgb = np.clip(rgb, 0, 255)
    raw = b''.join(b'\x00' + rgb[y].astype(np.uint8).tobytes() for y in range(h))
    chunk = lambda kind, body: struct.pack('>I', len(body)) + kind + body + struct.pack('>I', zlib.crc32(kind + body) & 0xFFFFFFFF)
    with open(path, 'wb') as f:
        f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)) +
                chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))


def shaded(x, y, z, w, h):
    """Lambert shading of the surface the pixels form (normals from the grid's differences)."""
    P = np.stack([x, y, z], 1).reshape(h, w, 3)
    du = np.zeros_like(P)
    dv = np.zeros_like(P)
    du[:, 1:-1] = P[:, 2:] - P[:, :-2]
    dv[1:-1] = P[2:] - P[:-2]
    n = np.cross(du, dv)
    n /= np.linalg.norm(n, axis=2, keepdims=True) + 1e-300
    light = np.array([0.3, -0.4, -1.0]) / np.linalg.norm([0.3, -0.4, -1.0])
    value = np.clip(np.abs(n @ light), 0, 1)
    value = np.where(np.isfinite(value), 40 + 200 * value, 0)
    value = np.where(np.isfinite(P).all(2), value, 0)
    return np.repeat(value[:, :, None], 3, axis=2)


def fill_picture(a):
    xi, yi, zi, w, h = read_pcd(a.input)
    xo, yo, zo, wo, ho = read_pcd(a.output)
    if (w, h) != (wo, ho):
        sys.exit('the output is %d x %d, the input %d x %d' % (wo, ho, w, h))
    rgb = shaded(xo, yo, zo, w, h)
    filled = (~np.isfinite(zi) & np.isfinite(zo)).reshape(h, w)
    rgb[filled] = rgb[filled] * np.array([1.0, 0.5, 0.1]) + np.array([40.0, 20.0, 0.0])  # orange, still shaded
    write_png(a.picture, rgb)
    print('%d filled pixels of %d without depth' % (filled.sum(), (~np.isfinite(zi)).sum()))


def edge_picture(a):
    r0, r1 = (int(v) for v in a.rows.split(':'))
    c0, c1 = (int(v) for v in a.cols.split(':'))
    views = []
    bounds = None
    for path in (a.input, a.output):
        x, y, z, w, h = read_pcd(path)
        sel = np.zeros((h, w), bool)
        sel[r0:r1, c0:c1] = True
        sel = sel.ravel() & np.isfinite(z)
        views.append((x[sel], z[sel]))
        if bounds is None:
            bounds = (x[sel].min(), x[sel].max(), z[sel].min(), z[sel].max())
    size = 400
    x_lo, x_hi, z_lo, z_hi = bounds
    span = max(x_hi - x_lo, z_hi - z_lo) * 1.05
    canvas = np.full((size, 2 * size + 10, 3), 255.0)
    for k, (x, z) in enumerate(views):
        px = ((x - x_lo) / span * (size - 1)).astype(int)
        pz = ((z - z_lo) / span * (size - 1)).astype(int)
        ok = (px >= 0) & (px < size) & (pz >= 0) & (pz < size)
        canvas[pz[ok], k * (size + 10) + px[ok]] = (20, 60, 160)
    canvas[:, size:size + 10] = 200
    write_png(a.picture, canvas)
    print('window rows %d:%d, columns %d:%d; %.3f m across' % (r0, r1, c0, c1, span))


def shade_picture(a):
    r0, r1 = (int(v) for v in a.rows.split(':'))
    c0, c1 = (int(v) for v in a.cols.split(':'))
    panels = []
    for path in (a.input, a.output):
        x, y, z, w, h = read_pcd(path)
        panel = shaded(x, y, z, w, h)[r0:r1, c0:c1]
        panels.append(np.kron(panel, np.ones((a.zoom, a.zoom, 1))))
    gap = np.full((panels[0].shape[0], 8, 3), 255.0)
    write_png(a.picture, np.concatenate([panels[0], gap, panels[1]], axis=1))
    print('window rows %d:%d, columns %d:%d' % (r0, r1, c0, c1))


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('kind', choices=['fill', 'edge', 'shade'])
    p.add_argument('input')
    p.add_argument('output')
    p.add_argument('picture')
    p.add_argument('--rows', default='200:260')
    p.add_argument('--cols', default='200:400')
    p.add_argument('--zoom', type=int, default=2)
    a = p.parse_args()
    {'fill': fill_picture, 'edge': edge_picture, 'shade': shade_picture}[a.kind](a)


if __name__ == '__main__':
    main()
