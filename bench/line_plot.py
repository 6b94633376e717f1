"""A dependency-free line plot (fig7_atoms' PNG canvas): several series, x linear or logarithmic,
y linear from 0 or logarithmic, numeric tick labels only (the legend goes in the caption)."""
import math

from fig7_atoms import Canvas

COLOURS = {"blue": (30, 80, 200), "red": (200, 40, 40), "green": (30, 150, 60), "orange": (230, 130, 20),
           "grey": (120, 120, 120), "purple": (130, 50, 170)}


def _ticks(lo, hi, log):
    if log:
        ticks = []
        for e in range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1):
            for m in (1, 2, 5):
                v = m * 10 ** e
                if lo <= v <= hi:
                    ticks.append(v)
        return ticks
    return [lo + (hi - lo) * i / 5 for i in range(6)]


def _label(v):
    if v == 0:
        return "0"
    if abs(v) >= 1e4 or abs(v) < 1e-2:
        return "%.0e" % v if float("%.0e" % v) == v else "%.1e" % v
    return ("%.2f" % v).rstrip("0").rstrip(".")


def line_plot(path, series, x_log=False, y_log=False, width=720, height=480):
    """series: list of (xs, ys, colour name, dashed). Writes a PNG."""
    left, right, top, bottom = 110, 30, 30, 60
    canvas = Canvas(width, height)
    xs = [x for s in series for x in s[0]]
    ys = [y for s in series for y in s[1]]
    if not xs:
        canvas.png(path)
        return
    x_lo, x_hi = min(xs), max(xs)
    if x_lo == x_hi:
        x_lo, x_hi = x_lo * 0.9 if x_log else x_lo - 1, x_hi * 1.1 if x_log else x_hi + 1
    if y_log:
        y_lo, y_hi = min(ys) / 1.3, max(ys) * 1.3
    else:
        y_lo, y_hi = 0.0, max(ys) * 1.1 if max(ys) > 0 else 1.0
    fx = (lambda v: math.log10(v)) if x_log else (lambda v: v)
    fy = (lambda v: math.log10(v)) if y_log else (lambda v: v)
    pad = 0.05 * (fx(x_hi) - fx(x_lo))
    ax_lo, ax_hi = fx(x_lo) - pad, fx(x_hi) + pad
    px = lambda v: round(left + (fx(v) - ax_lo) / (ax_hi - ax_lo) * (width - left - right))
    py = lambda v: round(height - bottom - (fy(v) - fy(y_lo)) / (fy(y_hi) - fy(y_lo)) * (height - top - bottom))
    black = (0, 0, 0)
    canvas.line(left, height - bottom, width - right, height - bottom, black)
    canvas.line(left, top, left, height - bottom, black)
    for v in _ticks(x_lo, x_hi, x_log) if x_log else sorted(set(xs)):
        canvas.line(px(v), height - bottom, px(v), height - bottom + 6, black)
        label = _label(v)
        canvas.text(px(v) - len(label) * 4, height - bottom + 12, label)
    for v in _ticks(y_lo, y_hi, y_log):
        canvas.line(left - 6, py(v), left, py(v), black)
        canvas.line(left + 1, py(v), width - right, py(v), (225, 225, 225))
        label = _label(v)
        canvas.text(left - 10 - len(label) * 8, py(v) - 5, label)
    for xs_, ys_, colour, dashed in series:
        rgb = COLOURS.get(colour, black)
        points = sorted(zip(xs_, ys_))
        for (x0, y0), (x1, y1) in zip(points, points[1:]):
            canvas.line(px(x0), py(y0), px(x1), py(y1), rgb, dash=6 if dashed else 0, thick=2)
        for x, y in points:
            for dx in range(-3, 4):
                for dy in range(-3, 4):
                    canvas.set(px(x) + dx, py(y) + dy, rgb)
    canvas.png(path)
