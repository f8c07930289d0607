#!/usr/bin/env python3
"""Writes the gesture files of this folder (CC0, made here for sylva).

Each is a made-up 3D gesture of a tracked stylus, in metres, up = +Z, the
tree's base at the origin: a trunk stroke (drawn slowly at the base and
faster towards the top, so the trunk tapers: Murakami et al. 5.2) and the
two side contours of a crown (the region-of-interest strokes of 4.2).
Run: python3 make_gestures.py  (writes next to itself; deterministic).
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def trunk_s_curve(n=80):
    """A gently S-curved trunk 6 m tall, drawn at 0.5 m/s at its base
    rising to 2 m/s at its tip: (t, x, y, z) samples."""
    points = []
    for i in range(n):
        u = i / (n - 1)
        points.append((0.35 * math.sin(math.pi * u * 1.5), 0.2 * math.sin(math.pi * u), 6.0 * u))
    samples, t = [], 0.0
    for i, p in enumerate(points):
        if i > 0:
            ds = math.dist(p, points[i - 1])
            t += ds / (0.5 + 1.5 * i / (n - 1))
        samples.append((t,) + p)
    return samples


def crown_contours(plane="xz", bottom=2.0, top=8.5, radius=3.0, n=40, centre=(0.2, 0.1)):
    """Left and right contours of a crown of revolution, drawn in `plane`."""
    strokes = []
    for side in (-1, 1):
        points = []
        for i in range(n):
            u = i / (n - 1)
            z = bottom + (top - bottom) * u
            r = radius * math.sin(math.pi * u) ** 0.7
            if plane == "xz":
                points.append((centre[0] + side * r, centre[1], z))
            else:
                points.append((centre[0], centre[1] + side * r, z))
        strokes.append(points)
    return strokes


def timed(points, speed=1.0, t0=0.0):
    samples, t = [], t0
    for i, p in enumerate(points):
        if i > 0:
            t += math.dist(p, points[i - 1]) / speed
        samples.append((t,) + tuple(p))
    return samples


def write_json():
    trunk = trunk_s_curve()
    strokes = [{"kind": "trunk", "samples": [[round(v, 6) for v in s] + [0.8] for s in trunk]}]
    t0 = trunk[-1][0] + 1.0
    for contour in crown_contours("xz"):
        samples = timed(contour, 1.5, t0)
        t0 = samples[-1][0] + 1.0
        strokes.append({"kind": "roi", "samples": [[round(v, 6) for v in s] for s in samples]})
    with open(os.path.join(HERE, "s_trunk.json"), "w") as f:
        json.dump({"format": "sylva-gesture", "version": 1, "strokes": strokes}, f, indent=None)
        f.write("\n")
    # Silhouette-based modelling (4.2): the crown alone.
    crown = [s for s in strokes if s["kind"] == "roi"]
    with open(os.path.join(HERE, "silhouette.json"), "w") as f:
        json.dump({"format": "sylva-gesture", "version": 1, "strokes": crown}, f, indent=None)
        f.write("\n")


def write_inkml():
    """A spiral trunk (Murakami fig. 10): two turns of a 0.5 m helix, 5 m tall."""
    n = 120
    lines = []
    points = []
    for i in range(n):
        u = i / (n - 1)
        a = 2 * math.pi * 2 * u
        points.append((0.5 * math.cos(a) - 0.5, 0.5 * math.sin(a), 5.0 * u))
    samples = timed(points, 1.2)
    trace = ", ".join("%.5f %.5f %.5f %.4f" % (x, y, z, t) for t, x, y, z in samples)
    lines.append('<?xml version="1.0" encoding="UTF-8"?>')
    lines.append('<ink xmlns="http://www.w3.org/2003/InkML">')
    lines.append("  <definitions>")
    lines.append('    <context xml:id="ctx0">')
    lines.append('      <traceFormat>')
    for name, unit in (("X", "m"), ("Y", "m"), ("Z", "m"), ("T", "s")):
        lines.append('        <channel name="%s" type="decimal" units="%s"/>' % (name, unit))
    lines.append("      </traceFormat>")
    lines.append("    </context>")
    lines.append("  </definitions>")
    lines.append('  <trace xml:id="trunk0" contextRef="#ctx0">' + trace + "</trace>")
    lines.append("</ink>")
    with open(os.path.join(HERE, "spiral.inkml"), "w") as f:
        f.write("\n".join(lines) + "\n")


def leaning_trunk(n=40):
    return [(0.6 * (i / (n - 1)) ** 2, -0.1 * i / (n - 1), 5.5 * i / (n - 1)) for i in range(n)]


def write_obj():
    trunk = leaning_trunk()
    # A second trunk stroke (a main branch) from the trunk at about 2.6 m.
    second = [(0.15 + 1.6 * u, 0.1 + 0.4 * u, 2.6 + 2.0 * u - 0.5 * u * u)
              for u in (i / 24 for i in range(25))]
    contours = crown_contours("yz", bottom=1.8, top=7.5, radius=2.6, centre=(0.4, 0.0))
    out = ["# sylva gesture file: polylines without time (datasets/gesture/README.md)"]
    groups = [("trunk", trunk), ("trunk2", second), ("roi_left", contours[0]),
              ("roi_right", contours[1])]
    count = 0
    for name, points in groups:
        out.append("g " + name)
        for p in points:
            out.append("v %.5f %.5f %.5f" % p)
        out.append("l " + " ".join(str(count + k + 1) for k in range(len(points))))
        count += len(points)
    with open(os.path.join(HERE, "two_trunks.obj"), "w") as f:
        f.write("\n".join(out) + "\n")


def write_ply():
    trunk = [(0.3 * math.sin(2.5 * u), 0.3 * (1 - math.cos(2.5 * u)), 5.0 * u)
             for u in (i / 49 for i in range(50))]
    contours = crown_contours("xz", bottom=1.5, top=7.0, radius=2.4, centre=(0.3, 0.2))
    vertices = [(p, 0) for p in trunk] + [(p, 1) for c in contours for p in c]
    edges = [(k, k + 1) for k in range(len(trunk) - 1)]
    start = len(trunk)
    for c in contours:
        edges += [(start + k, start + k + 1) for k in range(len(c) - 1)]
        start += len(c)
    out = ["ply", "format ascii 1.0", "comment sylva gesture: trunk and ROI polylines, no time",
           "element vertex %d" % len(vertices), "property float x", "property float y",
           "property float z", "property uchar roi", "element edge %d" % len(edges),
           "property int vertex1", "property int vertex2", "end_header"]
    out += ["%.5f %.5f %.5f %d" % (p[0], p[1], p[2], r) for p, r in vertices]
    out += ["%d %d" % e for e in edges]
    with open(os.path.join(HERE, "bent_trunk.ply"), "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    write_json()
    write_inkml()
    write_obj()
    write_ply()
