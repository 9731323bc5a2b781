# Writes crates/splineskin/assets/script.svg and script-scene.json: a line of calligraphic
# script drawn for splineskin, as a hand-digitised drawing comes out of an editor. Each of its
# four strokes is a closed outline of many short cubics (a broad nib held at 30 degrees along a
# wavy centre line); the junctions along the sides are saved as G1 in the scene, but their
# tangents are not all parallel: most are within 0.3 degrees, about one in eight is 0.5 to 3
# degrees off, a few are 4 to 13 degrees off, and some have the handle on the anchor (no
# tangent on that side until the next control point). Four Shepard handles stand outside the
# drawing. Deterministic (seeded); run: python3 tools/make_script.py
import json
import math
import os
import random

rng = random.Random(20261203)
NIB = math.radians(30.0)
SEGMENTS = 45          # cubics along each side of a stroke


def stroke(x0, y0, length, amp, freq, phase, wmax, wmin):
    """Centre line (x(s), y(s)), s in [0, 1], and the nib width there."""
    def c(s):
        return (x0 + length * s + 1.5 * math.sin(2 * math.pi * 3 * freq * s),
                y0 + amp * math.sin(2 * math.pi * freq * s + phase)
                + 0.1 * amp * math.sin(2 * math.pi * 1.7 * freq * s))

    def tangent(s):
        e = 1e-6
        a, b = c(max(0.0, s - e)), c(min(1.0, s + e))
        d = (b[0] - a[0], b[1] - a[1])
        n = math.hypot(*d)
        return (d[0] / n, d[1] / n)

    def width(s):
        t = tangent(s)
        ang = math.atan2(t[1], t[0])
        taper = math.sin(math.pi * (0.04 + 0.92 * s)) ** 0.35
        return (wmin + (wmax - wmin) * abs(math.sin(ang - NIB))) * taper
    return c, tangent, width


def side(c, tangent, width, sign, s):
    (tx, ty), w = tangent(s), width(s)
    p = c(s)
    q = (p[0] - sign * ty * w / 2, p[1] + sign * tx * w / 2)
    # Near the ends the stroke is cut along the nib's edge (30 degrees), not square: the two
    # sides are shifted along the centre line, in opposite directions.
    end = max(0.0, 1.0 - min(s, 1.0 - s) * 12.0)
    shift = sign * end * w * 0.8
    return (q[0] + shift * tx, q[1] + shift * ty)


def side_tangent(c, tangent, width, sign, s):
    e = 1e-5
    a = side(c, tangent, width, sign, max(0.0, s - e))
    b = side(c, tangent, width, sign, min(1.0, s + e))
    d = (b[0] - a[0], b[1] - a[1])
    n = math.hypot(*d)
    return (d[0] / n, d[1] / n)


def rotate(v, deg):
    a = math.radians(deg)
    return (v[0] * math.cos(a) - v[1] * math.sin(a), v[0] * math.sin(a) + v[1] * math.cos(a))


def kink():
    """Half the tangent angle a hand-digitised junction is off, in degrees, signed."""
    r = rng.random()
    if r < 0.80:
        half = rng.uniform(0.0, 0.15)
    elif r < 0.94:
        half = rng.uniform(0.25, 1.5)
    else:
        half = rng.uniform(2.0, 6.5)
    return half if rng.random() < 0.5 else -half


def outline(c, tangent, width):
    """Chain points of the closed outline: one side forward, a cap, the other side back, a cap."""
    pts = []
    for sign, order in ((1, range(SEGMENTS + 1)), (-1, range(SEGMENTS, -1, -1))):
        ss = [k / SEGMENTS for k in order]
        anchors = [side(c, tangent, width, sign, s) for s in ss]
        dirs = [side_tangent(c, tangent, width, sign, s) for s in ss]
        if sign < 0:
            dirs = [(-d[0], -d[1]) for d in dirs]
        halves = [kink() for _ in ss]
        # Handle on the anchor: no tangent on that side until the next control point.
        stacked = [rng.random() < 0.04 for _ in ss]
        for k in range(len(ss) - 1):
            p, q = anchors[k], anchors[k + 1]
            h = math.hypot(q[0] - p[0], q[1] - p[1]) / 3.0
            d0 = rotate(dirs[k], halves[k])
            d1 = rotate(dirs[k + 1], -halves[k + 1])
            c1 = (p[0] + h * d0[0], p[1] + h * d0[1])
            c2 = q if stacked[k + 1] and 0 < k + 1 < len(ss) - 1 else (q[0] - h * d1[0], q[1] - h * d1[1])
            if not pts:
                pts.append(p)
            pts += [c1, c2, q]
        # Cap to the other side: a straight cubic (corners at both ends), the nib's edge.
        start = pts[-1]
        end = side(c, tangent, width, -sign, ss[-1])
        pts += [(start[0] + (end[0] - start[0]) / 3, start[1] + (end[1] - start[1]) / 3),
                (start[0] + 2 * (end[0] - start[0]) / 3, start[1] + 2 * (end[1] - start[1]) / 3),
                end]
    pts[-1] = pts[0]
    return pts


def fmt(v):
    return f"{v:.2f}".rstrip("0").rstrip(".")


strokes = [
    stroke(40, 140, 150, 30, 1.5, 0.2, 11, 2.5),
    stroke(205, 150, 120, 26, 1.2, 1.6, 10, 2.0),
    stroke(340, 140, 175, 32, 1.8, 0.9, 11, 2.5),
    stroke(90, 240, 390, 10, 0.7, 2.4, 7, 1.5),   # the underline flourish
]
paths, junctions = [], []
for index, (c, t, w) in enumerate(strokes):
    pts = outline(c, t, w)
    d = "M " + " ".join(fmt(v) for v in pts[0])
    for k in range(1, len(pts), 3):
        d += " C " + " ".join(f"{fmt(a[0])} {fmt(a[1])}" for a in pts[k:k + 3])
    d += " Z"
    paths.append(d)
    n = (len(pts) - 1) // 3
    # Joints along the sides saved as G1 (joint k starts curve k; the caps' ends are corners).
    for k in range(n):
        if k in (0, SEGMENTS, SEGMENTS + 1, 2 * SEGMENTS + 1):
            continue
        junctions.append({"path": index, "joint": k, "kind": "G1"})

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "crates", "splineskin", "assets")
with open(os.path.join(here, "script.svg"), "w") as f:
    f.write('<svg xmlns="http://www.w3.org/2000/svg" width="560" height="300" viewBox="0 0 560 300">\n')
    f.write('  <title>splineskin example: a line of calligraphic script (hand-digitised junctions)</title>\n')
    f.write('  <g id="script" fill="#1d2a4d" stroke="none">\n')
    for i, d in enumerate(paths):
        f.write(f'    <path id="stroke{i + 1}" d="{d}"/>\n')
    f.write('  </g>\n</svg>\n')
scene = {
    "splineskin_scene": 1,
    "svg": "script.svg",
    "handles": [{"position": p} for p in ([10, 60], [550, 70], [540, 290], [20, 280])],
    "weights": {"family": "shepard"},
    "junctions": junctions,
    "poses": [
        {"name": "lean", "transforms": [{}, {"translate": [30, -25], "rotate": -12},
                                        {"translate": [45, 10], "rotate": 8}, {"translate": [-10, 5]}]},
        {"name": "squeeze", "transforms": [{"translate": [25, 20]}, {"translate": [-40, 15], "rotate": 15},
                                           {"translate": [-30, -20]}, {"translate": [20, -15], "rotate": -10}]},
    ],
}
with open(os.path.join(here, "script-scene.json"), "w") as f:
    json.dump(scene, f, indent=1)
    f.write("\n")
print(f"{sum(1 for _ in paths)} paths, {len(junctions)} saved G1 junctions")
