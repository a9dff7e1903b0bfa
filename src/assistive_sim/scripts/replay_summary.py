#!/usr/bin/env python3
"""Summarise a recorded replay (launch/replay.launch record:=FILE.bag).

Prints what the wearer would have felt (cues per mode and motor), how the pipeline kept up
(VO poses, maps, planner states per status, cue latency from the camera image stamp), writes a
top-down PNG of the last traversability grid with the VO trajectory and the path, and ends with
one JSON line.

    replay_summary.py FILE.bag [--png OUT.png]
"""
import argparse
import json
import os
import struct
import sys
import zlib

import rosbag

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


def render_map(path, grid, trajectory, plan, scale=8):
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

    plot(trajectory, (220, 40, 0), 1)
    plot(plan, (0, 180, 0), 1)
    rows = [bytes(v for c in row for v in c) for row in reversed(img)]  # y up
    write_png(path, W, H, rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bag")
    ap.add_argument("--png", default=None, help="map picture (default: replay_map.png beside the bag)")
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
    with rosbag.Bag(args.bag) as bag:
        for topic, msg, t in bag.read_messages():
            if topic == "/vo/odom":
                counts["vo_poses"] += 1
                p = msg.pose.pose.position
                trajectory.append((p.x, p.y))
            elif topic == "/obstacles/traversability":
                counts["maps"] += 1
                last_grid = msg
            elif topic == "/planner/state":
                counts["planner_states"] += 1
                name = STATUS.get(msg.status, "other")
                status[name] = status.get(name, 0) + 1
            elif topic == "/planner/path":
                counts["paths"] += 1
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
    if last_grid is not None:
        render_map(png, last_grid, trajectory, last_path)
        print(f"  map picture     {png}")
    out = dict(counts)
    out.update({f"cues_{k}": v for k, v in modes.items()})
    out.update({"latency_ms_median": med, "latency_ms_p99": p99, "map_png": png if last_grid else None})
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
