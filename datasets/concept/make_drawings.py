#!/usr/bin/env python3
"""Writes the concept-sketch test drawings of this folder (CC0, made for
sylva): one Inkscape-style SVG per phyllotactic pattern of Anastacio et al.
2006. Run from this folder: python3 make_drawings.py"""

HEADER = """<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg"
     xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
     width="200mm" height="300mm" viewBox="0 0 200 300">
"""


def layer(label, body, style):
    return (f'  <g inkscape:groupmode="layer" inkscape:label="{label}" style="{style}">\n'
            + body + "  </g>\n")


def path(d, ident=None):
    ident_attr = f' id="{ident}"' if ident else ""
    return f'    <path{ident_attr} d="{d}"/>\n'


def drawing(name, pattern, stem, left, right, inclinations, organs, labelled, note):
    construction = path(stem, "stem" if labelled else None)
    construction += path(left, "boundary-left" if labelled else None)
    construction += path(right, "boundary-right" if labelled else None)
    for k, d in enumerate(inclinations):
        construction += path(d, f"inclination-{k}" if labelled else None)
    body = HEADER + f"  <!-- {note} -->\n"
    body += layer("construction", construction, "fill:none;stroke:#000000;stroke-width:1.2")
    body += layer("organs", "".join(path(d) for d in organs), "fill:none;stroke:#2a6b1f;stroke-width:0.8")
    body += f'  <text x="10" y="295" font-size="8">{pattern}</text>\n</svg>\n'
    with open(name, "w") as f:
        f.write(body)


LEAF = "M 168 292 C 160 275 166 258 180 246 C 188 262 184 280 168 292 Z"
NARROW_LEAF = "M 150 292 C 146 280 150 266 156 254 C 160 268 158 282 150 292 Z"
ROUND_LEAF = "M 20 292 C 6 282 8 262 26 256 C 40 266 36 284 20 292 Z"

# Spiral: a cone-like bud, labelled lines, two leaf templates.
drawing("spiral.svg", "spiral",
        "M 100 285 C 101 200 99 120 100 25",
        "M 98 283 C 30 250 28 120 99 24",
        "M 102 283 C 170 250 172 120 101 24",
        ["M 40 228 L 100 252 L 160 228", "M 32 150 L 100 175 L 168 150",
         "M 45 70 L 100 100 L 155 70"],
        [LEAF, NARROW_LEAF], True, "spiral (137.5 deg); lines named by id")
# Monostichous: no ids, lines told apart by their shape; an upright shoot.
drawing("monostichous.svg", "monostichous",
        "M 100 288 C 96 210 104 110 100 20",
        "M 99 286 C 50 240 40 100 99 19",
        "M 101 286 C 150 240 160 100 101 19",
        ["M 50 220 L 100 240 L 150 220", "M 45 100 L 100 130 L 155 100"],
        [LEAF], False, "monostichous (30 deg); unlabelled lines")
# Distichous: a fan-shaped spray widening upwards.
drawing("distichous.svg", "distichous",
        "M 100 290 L 100 30",
        "M 99 290 C 70 250 20 120 60 40 C 75 20 90 25 99 30",
        "M 101 290 C 130 250 180 120 140 40 C 125 20 110 25 101 30",
        ["M 55 230 L 100 250 L 145 230", "M 30 140 L 100 160 L 170 140",
         "M 60 60 L 100 80 L 140 60"],
        [ROUND_LEAF], True, "distichous (180 deg)")
# Tristichous: a column with organs pointing slightly downwards at the base.
drawing("tristichous.svg", "tristichous",
        "M 100 288 L 100 22",
        "M 99 286 C 45 260 45 60 99 21",
        "M 101 286 C 155 260 155 60 101 21",
        ["M 40 262 L 100 255 L 160 262", "M 35 150 L 100 165 L 165 150",
         "M 50 60 L 100 85 L 150 60"],
        [NARROW_LEAF, LEAF], False, "tristichous (120 deg)")
# Tetrastichous: a tall shoot, organs at right angles.
drawing("tetrastichous.svg", "tetrastichous",
        "M 100 290 C 98 200 102 100 100 15",
        "M 99 289 C 60 260 55 60 99 14",
        "M 101 289 C 140 260 145 60 101 14",
        ["M 50 250 L 100 270 L 150 250", "M 45 150 L 100 170 L 155 150",
         "M 55 50 L 100 70 L 145 50"],
        [LEAF], True, "tetrastichous (90 deg)")
