#!/usr/bin/env python3
"""In-betweening on the LAFAN1 transition benchmark protocol (Harvey et al. 2020, "Robust Motion
In-betweening"), on the shared clips of one skeleton: MotionMap's inbetween beside the protocol's
two baselines, Zero-velocity and Interp.

The protocol as published (LAFAN1's benchmark), applied to a library instead of LAFAN1:
  * test windows of 65 frames every 40 frames of the held-out take(s) (a window starts at i while
    i + 65 < #frames); each window is centred on its root's mean floor position (x, z) and turned
    about the up axis so that the root faces +Z at frame 9, the last of the 10 context frames;
  * keys: frame 9 and frame 10 + n; the n frames 10 … 9 + n are predicted, n = 5, 15, 30, 45;
  * L2Q: the L2 norm of the difference of the global (forward-kinematics) joint quaternions,
    per frame, averaged over the predicted frames of every window (quaternions taken in the
    ground truth's hemisphere, joint by joint);
  * L2P: the same of the global joint positions, each coordinate of each joint normalised by the
    mean and standard deviation of the training set's (windows of 50 frames every 20 of the
    library's clips, prepared the same way);
  * NPSS: normalised power spectrum similarity (Gopalakrishnan et al. 2019) of the global
    quaternions over the predicted frames, weighted by the ground truth's power;
  * Zero-velocity repeats frame 9; Interp lerps the root's translation and slerps every local
    rotation between frame 9 and frame 10 + n.
MotionMap: the library's map (isomap, default options, every frame), and `motionmap.inbetween`
with keys (held-out clip, frame) — not in the map, so placed on it — and n frames between, by its
default route through the clips' own frames ("MotionMap") and by the grid route ("MM grid").

The split (kept here): the library is the Bandai Namco clips of ../shared/data/bandai but the
held-out take, dataset-1_walk_proud_001.bvh. (The CMU clips have another skeleton.)

usage: PYTHONPATH=build/python bench/inbetween_lafan.py [--data ../shared/data] [--tiny]
                                                          [--held-out TAKE]
--tiny: one window and n = 5 only (the ctest's case).
--held-out: another Bandai take to hold out (e.g. dataset-1_walk_old_001.bvh), to see how the
figures vary with the split; the protocol's split is the default.
"""
import argparse
import glob
import os
import sys

import numpy as np

import motionmap

HELD_OUT = "dataset-1_walk_proud_001.bvh"
LENGTHS = (5, 15, 30, 45)
N_PAST, N_FUTURE = 10, 10
TEST_WINDOW, TEST_OFFSET = 65, 40
TRAIN_WINDOW, TRAIN_OFFSET = 50, 20


# ---- quaternions (w, x, y, z), vectorised over leading axes -----------------------------------

def qmul(a, b):
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def qrot(q, v):
    """v rotated by unit quaternion q."""
    u = q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return v + q[..., :1] * t + np.cross(u, t)


def qslerp(a, b, t):
    """Slerp from a to b at fractions t (broadcast over a leading axis)."""
    dot = np.sum(a * b, axis=-1, keepdims=True)
    b = np.where(dot < 0, -b, b)
    dot = np.abs(dot)
    theta = np.arccos(np.clip(dot, -1.0, 1.0))
    s = np.sin(theta)
    small = s < 1e-9
    wa = np.where(small, 1.0 - t, np.sin((1.0 - t) * theta) / np.where(small, 1.0, s))
    wb = np.where(small, t, np.sin(t * theta) / np.where(small, 1.0, s))
    out = wa * a + wb * b
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def yaw(angle):
    """Quaternions of rotations by `angle` about +Y."""
    angle = np.asarray(angle, dtype=float)
    return np.stack([np.cos(angle / 2), np.zeros_like(angle), np.sin(angle / 2),
                     np.zeros_like(angle)], axis=-1)


def fk(rotations, translations, parents):
    """Global quaternions and positions (frames × joints × 4 / 3) from local ones."""
    gq = np.empty_like(rotations)
    gp = np.empty_like(translations)
    for j, p in enumerate(parents):
        if p < 0:
            gq[:, j], gp[:, j] = rotations[:, j], translations[:, j]
        else:
            gq[:, j] = qmul(gq[:, p], rotations[:, j])
            gp[:, j] = gp[:, p] + qrot(gq[:, p], translations[:, j])
    return gq, gp


# ---- windows ----------------------------------------------------------------------------------

class Take:
    def __init__(self, clip):
        self.clip = clip
        self.rot = clip.rotations
        self.trans = clip.translations
        self.parents = [int(p) for p in clip.skeleton.parents]
        # The joint that carries the motion (below a static joint_Root).
        moving = np.ptp(self.trans, axis=0).max(axis=1) > 1e-9
        self.root = int(np.argmax(moving)) if moving.any() else 0


def window_frame(gq, gp, root, anchor):
    """The rigid change of a window: centre on the root's mean floor position, face +Z at frame
    `anchor`. Returns (rotation quaternion, centre)."""
    centre = gp[:, root].mean(axis=0) * np.array([1.0, 0.0, 1.0])
    forward = qrot(gq[anchor, root], np.array([0.0, 0.0, 1.0]))
    return yaw(-np.arctan2(forward[0], forward[2])), centre


def to_window(gq, gp, turn, centre):
    q = qmul(np.broadcast_to(turn, gq.shape), gq)
    p = qrot(np.broadcast_to(turn, gp.shape[:-1] + (4,)), gp - centre)
    return q, p


def windows(take, size, offset):
    i = 0
    while i + size < take.clip.num_frames:
        yield i
        i += offset


def train_stats(takes):
    """Mean and standard deviation of every coordinate of every joint's global position over the
    training windows."""
    rows = []
    for take in takes:
        gq, gp = fk(take.rot, take.trans, take.parents)
        for i in windows(take, TRAIN_WINDOW, TRAIN_OFFSET):
            q, p = gq[i:i + TRAIN_WINDOW], gp[i:i + TRAIN_WINDOW]
            turn, centre = window_frame(q, p, take.root, N_PAST - 1)
            rows.append(to_window(q, p, turn, centre)[1].reshape(TRAIN_WINDOW, -1))
    x = np.concatenate(rows)
    return x.mean(axis=0), np.maximum(x.std(axis=0), 1e-9)


# ---- metrics -----------------------------------------------------------------------------------

def hemisphere(q, reference):
    return np.where(np.sum(q * reference, axis=-1, keepdims=True) < 0, -q, q)


def npss(gt, pred):
    """NPSS of (windows × frames × dims) sequences, weighted by the ground truth's power."""
    gt_power = np.square(np.real(np.fft.fft(gt, axis=1)))
    pred_power = np.square(np.real(np.fft.fft(pred, axis=1)))
    gt_total, pred_total = gt_power.sum(axis=1), pred_power.sum(axis=1)
    gt_cdf = np.cumsum(gt_power / np.maximum(gt_total[:, None], 1e-300), axis=1)
    pred_cdf = np.cumsum(pred_power / np.maximum(pred_total[:, None], 1e-300), axis=1)
    emd = np.abs(pred_cdf - gt_cdf).sum(axis=1)
    return float(np.average(emd, weights=gt_total))


# ---- the methods: local rotations and translations of the n transition frames ------------------

def zero_velocity(take, a, b):
    n = b - a - 1
    return np.repeat(take.rot[a:a + 1], n, axis=0), np.repeat(take.trans[a:a + 1], n, axis=0)


def interpolation(take, a, b):
    n = b - a - 1
    t = (np.arange(1, n + 1) / (n + 1))[:, None, None]
    rot = qslerp(take.rot[a][None], take.rot[b][None], t)
    trans = (1 - t) * take.trans[a][None] + t * take.trans[b][None]
    return rot, trans


def motionmap_inbetween(estimator, take, a, b, route):
    n = b - a - 1
    motion, _ = motionmap.inbetween(estimator, [(take.clip, a), (take.clip, b)], frames_between=n,
                                    route=route)
    return motion.rotations[1:n + 1], motion.translations[1:n + 1]


def evaluate(takes, stats, methods, lengths, max_windows):
    mean, std = stats
    results = {}
    for n in lengths:
        per = {name: {"l2q": [], "l2p": [], "gt_q": [], "q": []} for name in methods}
        for take in takes:
            gq_all, gp_all = fk(take.rot, take.trans, take.parents)
            for count, i in enumerate(windows(take, TEST_WINDOW, TEST_OFFSET)):
                if max_windows and count >= max_windows:
                    break
                window = slice(i, i + TEST_WINDOW)
                turn, centre = window_frame(gq_all[window], gp_all[window], take.root, N_PAST - 1)
                a, b = i + N_PAST - 1, i + N_PAST + n
                gq, gp = to_window(gq_all[a + 1:b], gp_all[a + 1:b], turn, centre)
                gpn = (gp.reshape(n, -1) - mean) / std
                for name, method in methods.items():
                    rot, trans = method(take, a, b)
                    q, p = fk(rot, trans, take.parents)
                    q, p = to_window(q, p, turn, centre)
                    q = hemisphere(q, gq)
                    pn = (p.reshape(n, -1) - mean) / std
                    d = per[name]
                    d["l2q"].extend(np.sqrt(np.sum((q - gq) ** 2, axis=(1, 2))))
                    d["l2p"].extend(np.sqrt(np.sum((pn - gpn) ** 2, axis=1)))
                    d["gt_q"].append(gq.reshape(n, -1))
                    d["q"].append(q.reshape(n, -1))
        for name, d in per.items():
            results[(name, n)] = (float(np.mean(d["l2q"])), float(np.mean(d["l2p"])),
                                  npss(np.stack(d["gt_q"]), np.stack(d["q"])))
        results[("windows", n)] = len(per[next(iter(methods))]["gt_q"])
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--data", default=os.path.join(here, "..", "..", "shared", "data"))
    parser.add_argument("--tiny", action="store_true", help="one window, n = 5 (the ctest)")
    parser.add_argument("--held-out", default=HELD_OUT, help="the Bandai take held out")
    args = parser.parse_args()
    folder = os.path.join(args.data, "bandai")
    paths = sorted(glob.glob(os.path.join(folder, "*.bvh")))
    if not paths or not os.path.exists(os.path.join(folder, HELD_OUT)):
        print(f"skipped: the Bandai clips are absent from {folder}")
        return 77
    if args.held_out not in [os.path.basename(p) for p in paths]:
        parser.error(f"--held-out: {args.held_out} is not a take in {folder}")
    library = [p for p in paths if os.path.basename(p) != args.held_out]
    held_out = [os.path.join(folder, args.held_out)]
    test = [Take(motionmap.load(p)) for p in held_out]
    if all(t.clip.num_frames <= TEST_WINDOW for t in test):
        parser.error(f"--held-out: {args.held_out} has {test[0].clip.num_frames} frames; a test "
                     f"window needs more than {TEST_WINDOW}")
    print(f"library: {len(library)} clips ({', '.join(os.path.basename(p) for p in library)})")
    print(f"held out: {args.held_out}")
    estimator = motionmap.Isomap().fit(library)
    train = [Take(motionmap.load(p)) for p in library]
    stats = train_stats(train)
    methods = {
        "MotionMap": lambda take, a, b: motionmap_inbetween(estimator, take, a, b, "clips"),
        "MM grid": lambda take, a, b: motionmap_inbetween(estimator, take, a, b, "grid"),
        "Interp": interpolation,
        "Zero-vel": zero_velocity,
    }
    lengths = (5,) if args.tiny else LENGTHS
    res = evaluate(test, stats, methods, lengths, 1 if args.tiny else 0)
    print(f"windows per length: {res[('windows', lengths[0])]}")
    for k, metric in enumerate(("L2Q", "L2P", "NPSS")):
        print(f"\n=== {metric} ===")
        print("{:<10}".format("n") + "".join(f" | {n:>7d}" for n in lengths))
        for name in methods:
            print("{:<10}".format(name) +
                  "".join(f" | {res[(name, n)][k]:7.4f}" for n in lengths))
    return 0


if __name__ == "__main__":
    sys.exit(main())
