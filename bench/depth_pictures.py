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
import os
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np


def read_pcd(path):
    """-> (x, y, z as float64 arrays, width, height)."""
    with open(path, 'rb') as f:
        data = f.read()
    header, offset = {}, 0
    while True:
        end = data.index(b'\n', offset)
        line = data[offset:end].decode('ascii', 'replace').strip()
        offset = end + 1
        if line and not line.startswith('#'):
            key, *values = line.split()
            header[key.upper()] = values
            if key.upper() == 'DATA':
                break
    if header['DATA'][0] == 'binary_compressed':
        with tempfile.TemporaryDirectory() as tmp:
            plain = os.path.join(tmp, 'plain.pcd')
            subprocess.run(['pcl_convert_pcd_ascii_binary', path, plain, '1'], check=True, capture_output=True)
            return read_pcd(plain)
    fields, sizes, types = header['FIELDS'], [int(s) for s in header['SIZE']], header['TYPE']
    counts = [int(c) for c in header.get('COUNT', ['1'] * len(fields))]
    n = int(header['POINTS'][0])
    dtype = np.dtype([(name if name != '_' else '_pad%d' % k, '<%s%d' % ({'F': 'f', 'U': 'u', 'I': 'i'}[t], s), (c,))
                      for k, (name, s, t, c) in enumerate(zip(fields, sizes, types, counts))])
    if header['DATA'][0] == 'binary':
        rows = np.frombuffer(data[offset:offset + n * dtype.itemsize], dtype)
        get = lambda name: rows[name][:, 0].astype(np.float64)
    else:
        table = np.array([ln.split() for ln in data[offset:].decode().splitlines() if ln.strip()], dtype=np.float64)
        column = {name: sum(counts[:k]) for k, name in enumerate(fields)}
        get = lambda name: table[:, column[name]]
    return get('x'), get('y'), get('z'), int(header['WIDTH'][0]), int(header['HEIGHT'][0])


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
