#!/usr/bin/env python3
"""The VO's online gyro bias against the truth, over a walk (issue 34).

usage: bias_trace.py DUMP [DUMP ...] [--every S]
  DUMP: a `vo_benchmark BAG --dump DUMP` file (one row per frame: stamp state keyframe inliers,
  truth x y z qx qy qz qw, estimate x y z qx qy qz qw, the frame's integrated gyro qx qy qz qw
  (camera_link), the bias estimate bx by bz (camera_link, rad/s), accelerometer, trusted, holding).

The truth's bias is what the gyro adds to the true rotation on each frame, log(R_true^T R_gyro)/dt in
camera_link, averaged over 3 s (the gyro's noise averages out, its slow bias walk stays). Prints,
every S seconds (default 2), the tracking state, the estimate and the truth in deg/s and their
distance; then the constant fit over the walk (the bias vo_benchmark's gyro floor fits), the time
of the estimate's first change, and the error's mean and 90th percentile. A bias error of e deg/s
costs about e deg/m of rotational drift at 1 m/s wherever the gyro carries the orientation.
"""
import sys

import numpy as np

R_LINK_OPTICAL = np.array([[0, 0, 1], [-1, 0, 0], [0, -1, 0]], float)  # assistive_vo/frames.h


def quat_to_matrix(q):
    x, y, z, w = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                     np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                     np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], -2)


def log_map(R):
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return v / 2 if angle < 1e-9 else v * angle / (2 * np.sin(angle))


def trace(path, every_s):
    d = np.loadtxt(path)
    t, state = d[:, 0], d[:, 1].astype(int)
    truth = quat_to_matrix(d[:, 7:11])
    gyro = quat_to_matrix(d[:, 18:22])
    est = d[:, 22:25]
    per_frame = []
    for k in range(1, len(t)):
        R_true_link = R_LINK_OPTICAL @ truth[k - 1].T @ truth[k] @ R_LINK_OPTICAL.T
        per_frame.append(log_map(R_true_link.T @ gyro[k]) / (t[k] - t[k - 1]))
    per_frame = np.array(per_frame)
    half = int(round(1.5 * 15))
    true_bias = np.array([per_frame[max(0, k - half):k + half].mean(0) for k in range(len(per_frame))])
    err = np.linalg.norm(est[1:] - true_bias, axis=1) * 180 / np.pi
    deg = 180 / np.pi
    print(f"{path}: {len(t)} frames, {t[-1] - t[0]:.1f} s")
    next_t = t[0]
    for k in range(1, len(t)):
        if t[k] >= next_t:
            print(f"  {t[k] - t[0]:6.1f} s  state {state[k]}  estimate {np.round(est[k] * deg, 3)}  "
                  f"truth {np.round(true_bias[k - 1] * deg, 3)}  error {err[k - 1]:.3f} deg/s")
            next_t += every_s
    moved = np.nonzero(np.linalg.norm(est - est[0], axis=1) > 0)[0]
    first = f"{t[moved[0]] - t[0]:.1f} s" if len(moved) else "never"
    print(f"  constant fit {np.round(per_frame.mean(0) * deg, 4)} deg/s; first change of the estimate {first}; "
          f"error mean {err.mean():.4f}, p90 {np.percentile(err, 90):.4f} deg/s")


def main(argv):
    every_s = 2.0
    paths = []
    it = iter(argv)
    for a in it:
        if a == "--every":
            every_s = float(next(it))
        else:
            paths.append(a)
    if not paths:
        print(__doc__)
        return 1
    for p in paths:
        trace(p, every_s)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
