#!/usr/bin/env python3
"""Writes the scenes in motion of the benchmark suite (`vphys peers rapier --suite`).

Run from anywhere: `python3 host/physics/scenes/suite/generate.py`
(`--trees-at-one-point PATH` writes the uncommitted scene of the bad-input figure instead). The scenes are
deterministic (a fixed seed each): running it again writes the same files. Every body is
unrotated (the rapier peer's translation takes unrotated boxes and spheres), the ground is
the half-space z >= 0, the step is 1/60 s and the solver takes its defaults.
"""
import json
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
EFFECTS = ["gravity", "contacts", "friction"]


def ground():
    return {"name": "ground", "kind": "fixed",
            "shape": {"type": "half_space", "normal": [0, 0, 1]}}


def box(pos, h=0.5, mass=1.0, kind=None):
    b = {"shape": {"type": "box", "half_extents": [h, h, h] if isinstance(h, float) else h},
         "position": [round(x, 6) for x in pos]}
    if kind:
        b["kind"] = kind
    else:
        b["mass"] = mass
    return b


def sphere(pos, r=0.5, mass=1.0):
    return {"shape": {"type": "sphere", "radius": r}, "mass": mass,
            "position": [round(x, 6) for x in pos]}


def scene(name, steps, bodies):
    return {"name": name, "dt": 1.0 / 60.0, "steps": steps, "gravity": [0, 0, -9.81],
            "effects": EFFECTS, "bodies": [ground()] + bodies}


def rain(n, side, seed):
    """n unit boxes over a side x side grid of columns, falling onto the ground and each
    other: each column's boxes 2 m apart, every box jittered by up to 0.2 m."""
    rng = random.Random(seed)
    bodies = []
    for i in range(n):
        col, layer = i % (side * side), i // (side * side)
        x = (col % side - (side - 1) / 2) * 1.6 + rng.uniform(-0.2, 0.2)
        y = (col // side - (side - 1) / 2) * 1.6 + rng.uniform(-0.2, 0.2)
        z = 1.0 + 2.0 * layer + rng.uniform(0.0, 0.4)
        bodies.append(box([x, y, z]))
    return bodies


def walls(half, height, thick=0.5):
    """Four fixed walls round the square |x|, |y| <= half."""
    out = []
    for sx, sy in [(1, 0), (-1, 0), (0, 1), (0, -1)]:
        he = [thick, half + 2 * thick, height / 2] if sx else [half + 2 * thick, thick, height / 2]
        pos = [sx * (half + thick), sy * (half + thick), height / 2]
        out.append({"kind": "fixed", "shape": {"type": "box", "half_extents": he},
                    "position": pos})
    return out


def heap(spheres, boxes, half, seed):
    """Spheres and boxes of mixed sizes dropped into a walled bin."""
    rng = random.Random(seed)
    kinds = ["s"] * spheres + ["b"] * boxes
    rng.shuffle(kinds)
    side = int(2 * half / 1.2)
    bodies = walls(half, 6.0)
    for i, k in enumerate(kinds):
        col, layer = i % (side * side), i // (side * side)
        x = -half + 0.6 + (col % side) * 1.2 + rng.uniform(-0.05, 0.05)
        y = -half + 0.6 + (col // side) * 1.2 + rng.uniform(-0.05, 0.05)
        z = 0.8 + 1.25 * layer
        if k == "s":
            r = rng.uniform(0.3, 0.5)
            bodies.append(sphere([x, y, z], r, mass=round(4.19 * r ** 3 * 1000 / 1000, 6)))
        else:
            h = [rng.uniform(0.25, 0.45) for _ in range(3)]
            bodies.append(box([x, y, z], [round(v, 4) for v in h],
                              mass=round(8 * h[0] * h[1] * h[2], 6)))
    return bodies


def pyramid(base, h=0.5, gap=0.05):
    out = []
    for row in range(base):
        n = base - row
        for i in range(n):
            x = (i - (n - 1) / 2) * (2 * h + gap)
            out.append(box([x, 0.0, h + row * 2 * h]))
    return out


def wreck(base, ball_mass, drop):
    """A pyramid of unit boxes and a heavy ball dropped onto its top from `drop` m above."""
    bodies = pyramid(base)
    top = base * 1.0
    bodies.append(sphere([0.0, 0.0, top + drop + 1.0], 1.0, mass=ball_mass))
    return bodies


def small_pyramids(count, base):
    """`count` pyramids of `base` boxes in a row, 4 m apart."""
    out = []
    for k in range(count):
        for b in pyramid(base):
            b["position"][1] = round((k - (count - 1) / 2) * 4.0, 6)
            out.append(b)
    return out


def tumbling(boxes, spheres, half, seed):
    """Boxes and spheres of mixed sizes thrown into a walled bin, each turned at random and
    spinning at up to 8 rad/s about a random axis, moving at up to 3 m/s."""
    rng = random.Random(seed)
    kinds = ["b"] * boxes + ["s"] * spheres
    rng.shuffle(kinds)
    side = int(2 * half / 1.3)
    # Walls above the highest layer (eleven layers of 1.4 m from 1 m) and its throw.
    bodies = walls(half, 20.0)

    def rand_vec(scale):
        return [round(rng.uniform(-scale, scale), 6) for _ in range(3)]

    for i, k in enumerate(kinds):
        col, layer = i % (side * side), i // (side * side)
        x = -half + 0.65 + (col % side) * 1.3
        y = -half + 0.65 + (col // side) * 1.3
        z = 1.0 + 1.4 * layer
        if k == "s":
            r = rng.uniform(0.3, 0.5)
            b = sphere([x, y, z], r, mass=round(4.19 * r ** 3, 6))
        else:
            h = [rng.uniform(0.25, 0.45) for _ in range(3)]
            b = box([x, y, z], [round(v, 4) for v in h], mass=round(8 * h[0] * h[1] * h[2], 6))
            b["rotation"] = rand_vec(3.0)
        b["velocity"] = rand_vec(3.0)
        w = rand_vec(1.0)
        n = max(sum(c * c for c in w) ** 0.5, 1e-9)
        spin = rng.uniform(2.0, 8.0)
        b["angular_velocity"] = [round(c / n * spin, 6) for c in w]
        bodies.append(b)
    return bodies


def chains(count, half, seed):
    """`count` copies of `chain-on-boxes.json`'s ten-link chain (capsule links on hinges about
    alternating axes, a floating base) dropped in layers into a walled bin of half-width
    `half`, each turned about the vertical and bent at random, to fall onto the ground and
    onto each other. A chain's middle lies within 0.3 m of the bin's centre and its ends
    within 0.5 m of its middle: inside the bin."""
    rng = random.Random(seed)
    with open(os.path.join(HERE, "..", "chain-on-boxes.json")) as f:
        tree = json.load(f)["articulated"][0]
    trees = []
    for i in range(count):
        yaw = rng.uniform(-math.pi, math.pi)
        # The chain runs 1 m along its base's x axis: start it so that its middle is over a
        # point of the bin, 0.12 m above the layer below.
        cx, cy = rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)
        z = 0.1 + 0.12 * i
        base = [cx - 0.5 * math.cos(yaw), cy - 0.5 * math.sin(yaw), z]
        # Bent only about the vertical hinges (links 2, 4, 6, 8), so that each chain lies in its
        # own layer until it lands.
        bends = [round(rng.uniform(-0.4, 0.4), 6) if k % 2 == 1 else 0.0 for k in range(9)]
        trees.append({"model": tree["model"], "shapes": tree["shapes"],
                      "q": [0.0, 0.0, round(yaw, 6)] + [round(c, 6) for c in base] + bends})
    return trees


def chains_scene(name, steps, count, half, seed):
    s = scene(name, steps, walls(half, 4.0))
    s["effects"] = EFFECTS + ["articulated", "continuous_collision"]
    s["articulated"] = chains(count, half, seed)
    return s


SCENES = {
    "rain-1000": scene("1000 unit boxes raining onto the ground and each other", 300,
                       rain(1000, 10, 1)),
    "rain-400": scene("400 unit boxes raining onto the ground and each other", 300,
                      rain(400, 8, 2)),
    "heap-1000": scene("600 spheres and 400 boxes of mixed sizes falling into a walled bin",
                       480, heap(600, 400, 6.0, 3)),
    "heap-300": scene("200 spheres and 100 boxes of mixed sizes falling into a walled bin",
                      480, heap(200, 100, 4.0, 4)),
    "wreck-210": scene("a 200 kg ball dropped onto a 210-box pyramid", 360,
                       wreck(20, 200.0, 2.0)),
    "wreck-120": scene("a 1000 kg ball dropped onto a 120-box pyramid", 360,
                       wreck(15, 1000.0, 4.0)),
    "pyramids-20x10": scene("20 pyramids of 55 boxes each (base 10)", 300,
                            small_pyramids(20, 10)),
    "tumble-500": scene("300 boxes and 200 spheres of mixed sizes thrown spinning into a "
                        "walled bin", 360, tumbling(300, 200, 5.0, 5)),
    "chains-24": chains_scene("24 ten-link chains falling onto the ground and each other in a "
                              "walled bin", 360, 24, 1.0, 6),
}


def trees_at_one_point(path, copies=1000):
    """Writes `copies` copies of `chain-on-boxes.json`'s tree, all at one point, to `path`:
    the scene the engine refuses before its first step (bodies overlapping en masse). Not
    committed: 2.5 MB of JSON."""
    with open(os.path.join(HERE, "..", "chain-on-boxes.json")) as f:
        s = json.load(f)
    s["articulated"] = [s["articulated"][0]] * copies
    with open(path + ".tmp", "w") as f:
        json.dump(s, f, separators=(",", ":"))
    os.replace(path + ".tmp", path)
    print(f"wrote {path} ({copies} trees at one point)")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--trees-at-one-point":
        trees_at_one_point(sys.argv[2])
        return
    if len(sys.argv) != 1:
        sys.exit("usage: generate.py [--trees-at-one-point PATH]")
    for name, s in SCENES.items():
        path = os.path.join(HERE, name + ".json")
        with open(path + ".tmp", "w") as f:
            json.dump(s, f, separators=(",", ":"))
            f.write("\n")
        os.replace(path + ".tmp", path)
        print(f"wrote {path} ({len(s['bodies'])} bodies)")


if __name__ == "__main__":
    main()
