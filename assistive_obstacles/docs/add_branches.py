#!/usr/bin/env python3
"""Branches at head height beside a generated world's walk (issue 36, an analysis aid).

    add_branches.py WORLD.yaml OUT.yaml SEED

Every 3-5 m along the walk's waypoint polyline, a 0.6 x 0.3 m overhang (0.25 m thick, yawed along
the walk) 0.55-0.9 m to one side of the walk's line, its bottom drawn uniformly from 1.50 m to the
truth's head limit less 3 cm (eye height + 0.27 m, assistive_sim OccupancyParams), so that the
ground truth counts each one as an obstacle. The walk itself is unchanged. Render with
`render_bag --world OUT.yaml --depth` and score with `obstacles_benchmark --gt-depth`
(docs/results/assistive_obstacles.md, "Branches above the eye").
"""
import math
import random
import re
import sys


def main():
    src, dst, seed = sys.argv[1], sys.argv[2], int(sys.argv[3])
    rng = random.Random(seed)
    text = open(src).read()
    waypoints = [[float(v) for v in p.split(',')]
                 for p in re.findall(r'\[([-\d.]+, [-\d.]+)\]', re.search(r'waypoints: (\[\[.*?\]\])', text).group(1))]
    eye = float(re.search(r'eye_height: ([\d.]+)', text).group(1))
    top = eye + 0.27
    elements = []
    for (x0, y0), (x1, y1) in zip(waypoints, waypoints[1:]):
        length = math.hypot(x1 - x0, y1 - y0)
        if length < 1e-6:
            continue
        ux, uy = (x1 - x0) / length, (y1 - y0) / length
        s = rng.uniform(1, 3)
        while s < length - 1:
            side, off = rng.choice([-1, 1]), rng.uniform(0.55, 0.9)
            cx, cy = x0 + ux * s - side * uy * off, y0 + uy * s + side * ux * off
            bottom = rng.uniform(1.50, top - 0.03)
            elements.append(f"  - {{type: overhang, center: [{cx:.3f}, {cy:.3f}], size: [0.600, 0.300], "
                            f"bottom: {bottom:.3f}, top: {bottom + 0.25:.3f}, yaw: {math.degrees(math.atan2(uy, ux)):.1f}, "
                            f"material: wood}}  # a branch")
            s += rng.uniform(3, 5)
    i = text.index('trajectory:')
    open(dst, 'w').write(text[:i] + '\n'.join(elements) + '\n' + text[i:])
    print(f"{len(elements)} branches, the truth's head limit {top:.3f} m")


if __name__ == '__main__':
    main()
