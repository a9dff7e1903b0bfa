#!/usr/bin/env python3
"""Summarise a recorded replay (launch/replay.launch record:=FILE.bag).

Prints what the wearer would have felt (cues per mode and motor), how the pipeline kept up
(VO poses, maps, planner states per status, cue latency from the camera image stamp), writes a
top-down PNG of the last traversability grid with the VO trajectory and the path, and ends with
one JSON line.

    replay_summary.py FILE.bag [--png OUT.png] [--at T] [--world W.yaml]

--at T: the grid and the path the chain had T s after the bag's start (default: the last ones).
--world W.yaml: a closed-loop trial's bag (`mobility_trials --mode vision --record DIR`, which also
keeps /sim/camera_pose, the truth): the world's walls (magenta), its other elements (purple), the
true walk (blue) and the places (cyan) drawn in the map's frame, placed by a rigid fit of the true
walk to the VO's over the first 30 s.
"""
import argparse
import json
import math
import os
import struct
import sys
import zlib

import rosbag
import yaml

TOPICS = ["/vo/odom", "/obstacles/traversability", "/planner/state", "/planner/path", "/tactile/cue",
          "/sim/camera_pose"]

MODES = {0: "idle", 1: "guidance", 2: "proximity", 3: "alert", 4: "unsure"}
MOTORS = ["left_shoulder", "right_shoulder", "left_waist", "right_waist"]
STATUS = {0: "ok", 1: "no_pose", 2: "no_map", 3: "in_unknown", 4: "no_path", 5: "no_waypoint"}


def write_png(path, width, height, rows):
    """rows: list of bytes objects, RGB, one per image row (top first)."""
    raw = b"".join(b"\x00" + r for r in rows)

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def world_overlay(world, truth, vo, walked, fit_s=30.0):
    """The world's walls, elements, true walk (`walked`: the truth's (x, y) up to the shown time)
    and places in the VO's frame: (segments, points) lists of (points, colour). The fit: the 2-D
    rotation and translation that take the true walk onto the VO's over their first fit_s seconds
    (matched by time, over the whole bag whatever time is shown)."""
    pairs, j = [], 0
    for t, q in vo:
        if t - vo[0][0] > fit_s:
            break
        while j + 1 < len(truth) and truth[j + 1][0] <= t:
            j += 1
        pairs.append((truth[j][1], q))
    if len(pairs) < 2:
        return [], []
    n = len(pairs)
    pc = [sum(p[0][k] for p in pairs) / n for k in (0, 1)]
    qc = [sum(p[1][k] for p in pairs) / n for k in (0, 1)]
    cross = dot = 0.0
    for p, q in pairs:
        ax, ay, bx, by = p[0] - pc[0], p[1] - pc[1], q[0] - qc[0], q[1] - qc[1]
        cross += ax * by - ay * bx
        dot += ax * bx + ay * by
    a = math.atan2(cross, dot)
    c, s_ = math.cos(a), math.sin(a)

    def to_map(x, y):
        x, y = x - pc[0], y - pc[1]
        return (c * x - s_ * y + qc[0], s_ * x + c * y + qc[1])

    segments, points = [], []
    for e in world.get("elements", []):
        if e.get("type") == "wall":
            segments.append(([to_map(*e["from"]), to_map(*e["to"])], (200, 0, 200)))
        elif "center" in e and "size" in e:
            hx, hy = e["size"][0] / 2, e["size"][1] / 2
            yaw = math.radians(e.get("yaw", 0.0))
            cy, sy = math.cos(yaw), math.sin(yaw)
            corners = [(e["center"][0] + cy * u - sy * v, e["center"][1] + sy * u + cy * v)
                       for u, v in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy))]
            segments.append(([to_map(*p) for p in corners], (140, 0, 255)))
        elif "center" in e and "radius" in e:
            r = e["radius"]
            ring = [(e["center"][0] + r * math.cos(k * math.pi / 8), e["center"][1] + r * math.sin(k * math.pi / 8))
                    for k in range(17)]
            segments.append(([to_map(*p) for p in ring], (140, 0, 255)))
    points.append(([to_map(*p) for p in walked], (0, 110, 255), 0))
    points.append(([to_map(*p) for p in world.get("trajectory", {}).get("waypoints", [])], (0, 200, 200), 3))
    return segments, points


def render_map(path, grid, trajectory, plan, scale=8, segments=(), points=()):
    w, h = grid.info.width, grid.info.height
    res = grid.info.resolution
    ox, oy = grid.info.origin.position.x, grid.info.origin.position.y
    colours = {-1: (128, 128, 128), 0: (255, 255, 255), 50: (255, 200, 0), 100: (0, 0, 0)}
    img = [[colours.get(v if v in colours else (100 if v > 50 else 0), (0, 0, 0))
            for v in grid.data[r * w:(r + 1) * w]] for r in range(h)]
    img = [[c for c in row for _ in range(scale)] for row in img for _ in range(scale)]
    W, H = w * scale, h * scale

    def plot(points, colour, size):
        for x, y in points:
            cx, cy = int((x - ox) / res * scale), int((y - oy) / res * scale)
            for dy in range(-size, size + 1):
                for dx in range(-size, size + 1):
                    px, py = cx + dx, cy + dy
                    if 0 <= px < W and 0 <= py < H:
                        img[py][px] = colour

    for line, colour in segments:
        for (x0, y0), (x1, y1) in zip(line, line[1:]):
            n = max(1, int(math.hypot(x1 - x0, y1 - y0) / res * scale * 2))
            plot([(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n) for k in range(n + 1)], colour, 0)
    for pts, colour, size in points:
        plot(pts, colour, size)
    plot(trajectory, (220, 40, 0), 1)
    plot(plan, (0, 180, 0), 1)
    rows = [bytes(v for c in row for v in c) for row in reversed(img)]  # y up
    write_png(path, W, H, rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bag")
    ap.add_argument("--png", default=None, help="map picture (default: replay_map.png beside the bag)")
    ap.add_argument("--at", type=float, default=None, help="the grid and path T s after the bag's start")
    ap.add_argument("--world", default=None, help="the trial's world YAML: its walls drawn in the map's frame")
    args = ap.parse_args()
    if not os.path.exists(args.bag):
        print(f"replay_summary: no such bag: {args.bag}", file=sys.stderr)
        print(json.dumps({"vo_poses": None, "cues": None}))
        return 1
    png = args.png or os.path.join(os.path.dirname(os.path.abspath(args.bag)), "replay_map.png")

    counts = {"vo_poses": 0, "maps": 0, "planner_states": 0, "paths": 0, "cues": 0}
    modes = {m: 0 for m in MODES.values()}
    motor_on = {m: 0 for m in MOTORS}
    status = {s: 0 for s in STATUS.values()}
    latencies = []
    trajectory, last_grid, last_path = [], None, []
    vo_timed, truth, walked = [], [], []  # (t, (x, y)) for --world's fit; (x, y) up to --at
    with rosbag.Bag(args.bag) as bag:
        t0 = bag.get_start_time()
        for topic, msg, t in bag.read_messages(topics=TOPICS):
            shown = args.at is None or t.to_sec() - t0 <= args.at
            if topic == "/vo/odom":
                counts["vo_poses"] += 1
                p = msg.pose.pose.position
                vo_timed.append((t.to_sec(), (p.x, p.y)))
                if shown:
                    trajectory.append((p.x, p.y))
            elif topic == "/sim/camera_pose":
                truth.append((t.to_sec(), (msg.pose.position.x, msg.pose.position.y)))
                if shown:
                    walked.append(truth[-1][1])
            elif topic == "/obstacles/traversability":
                counts["maps"] += 1
                if shown:
                    last_grid = msg
            elif topic == "/planner/state":
                counts["planner_states"] += 1
                name = STATUS.get(msg.status, "other")
                status[name] = status.get(name, 0) + 1
            elif topic == "/planner/path":
                counts["paths"] += 1
                if shown:
                    last_path = [(ps.pose.position.x, ps.pose.position.y) for ps in msg.poses]
            elif topic == "/tactile/cue":
                counts["cues"] += 1
                name = MODES.get(msg.mode, "other")
                modes[name] = modes.get(name, 0) + 1
                for i, m in enumerate(MOTORS):
                    motor_on[m] += msg.intensity[i] > 0.0
                if msg.source_stamp.to_sec() > 0:
                    latencies.append((t - msg.source_stamp).to_sec() * 1e3)
    latencies.sort()
    med = latencies[len(latencies) // 2] if latencies else None
    p99 = latencies[min(len(latencies) - 1, int(0.99 * len(latencies)))] if latencies else None

    print("replay summary")
    for k, v in counts.items():
        print(f"  {k:<16} {v}")
    print("  planner status  " + ", ".join(f"{k} {v}" for k, v in status.items() if v))
    print("  cue modes       " + ", ".join(f"{k} {v}" for k, v in modes.items()))
    print("  motor on        " + ", ".join(f"{k} {v}" for k, v in motor_on.items()))
    if med is not None:
        print(f"  cue latency     median {med:.1f} ms, p99 {p99:.1f} ms (image stamp -> cue, simulated clock)")
    segments, points = [], []
    if args.world:
        if not truth:
            print("replay_summary: --world: the bag has no /sim/camera_pose (the truth); the world is not drawn",
                  file=sys.stderr)
        else:
            with open(args.world) as f:
                segments, points = world_overlay(yaml.safe_load(f), truth, vo_timed, walked)
    if last_grid is not None:
        render_map(png, last_grid, trajectory, last_path, segments=segments, points=points)
        print(f"  map picture     {png}")
    out = dict(counts)
    out.update({f"cues_{k}": v for k, v in modes.items()})
    out.update({"latency_ms_median": med, "latency_ms_p99": p99, "map_png": png if last_grid else None})
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
