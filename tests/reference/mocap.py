"""An independent NumPy/SciPy implementation of MotionMap's map inputs, for reference fixtures.

Parses BVH, runs forward kinematics with scipy.spatial.transform.Rotation and builds the same
matrices the C++ library documents (src/motionmap/features/features.h):
  X  frames x 4(J-1): local rotation quaternions (w, x, y, z) of every non-root joint,
     sign-consistent over rows (row 0: w >= 0; later rows flip a joint whose dot product with the
     previous row's is negative);
  D  frames x frames: Euclidean distance between heading-local point clouds (all joints and end
     sites after removing the root's floor translation and heading about +Y).
A leading bind pose (frame 0 farther from frame 1 than 10x the median later consecutive step) is
left out. Shares no code with the C++ side.
"""
import numpy as np
from scipy.spatial.distance import cdist
from scipy.spatial.transform import Rotation


def parse_bvh(path):
    with open(path) as f:
        tokens = f.read().split()
    joints = []  # dicts: name, parent, offset, channels, end_sites
    stack, i = [], 0
    assert tokens[i] == "HIERARCHY"
    i += 1
    while tokens[i] != "MOTION":
        t = tokens[i]
        if t in ("ROOT", "JOINT"):
            joints.append(dict(name=tokens[i + 1], parent=stack[-1] if stack else -1,
                               offset=None, channels=[], end_sites=[]))
            i += 2
            assert tokens[i] == "{"
            stack.append(len(joints) - 1)
            i += 1
        elif t == "End":
            assert tokens[i + 1] == "Site" and tokens[i + 2] == "{" and tokens[i + 3] == "OFFSET"
            joints[stack[-1]]["end_sites"].append(np.array([float(v) for v in tokens[i + 4:i + 7]]))
            assert tokens[i + 7] == "}"
            i += 8
        elif t == "OFFSET":
            joints[stack[-1]]["offset"] = np.array([float(v) for v in tokens[i + 1:i + 4]])
            i += 4
        elif t == "CHANNELS":
            n = int(tokens[i + 1])
            joints[stack[-1]]["channels"] = tokens[i + 2:i + 2 + n]
            i += 2 + n
        elif t == "}":
            stack.pop()
            i += 1
        else:
            raise ValueError(f"unexpected token {t}")
    assert tokens[i + 1] == "Frames:" and tokens[i + 3] == "Frame" and tokens[i + 4] == "Time:"
    frames = int(tokens[i + 2])
    frame_time = float(tokens[i + 5])
    channels = sum(len(j["channels"]) for j in joints)
    values = np.array([float(v) for v in tokens[i + 6:i + 6 + frames * channels]])
    return joints, values.reshape(frames, channels), frame_time


def local_transforms(joints, values):
    """Per joint: (frames x 3 translations, Rotation of frames local rotations)."""
    frames = values.shape[0]
    out, col = [], 0
    for j in joints:
        trans = np.tile(j["offset"], (frames, 1))
        axes, angle_cols = "", []
        for c in j["channels"]:
            axis = c[0].lower()
            if c.endswith("position"):
                trans[:, "xyz".index(axis)] = values[:, col]
            else:
                axes += axis.upper()  # upper case: intrinsic, so "ZYX" is R = Rz·Ry·Rx
                angle_cols.append(col)
            col += 1
        if axes:
            rot = Rotation.from_euler(axes, values[:, angle_cols], degrees=True)
        else:
            rot = Rotation.identity(frames)
        out.append((trans, rot))
    return out


def world_points(joints, values):
    """frames x P x 3 world positions of joints then end sites, and the world root rotations."""
    local = local_transforms(joints, values)
    pos, rot = [None] * len(joints), [None] * len(joints)
    for k, j in enumerate(joints):
        t, r = local[k]
        if j["parent"] < 0:
            pos[k], rot[k] = t, r
        else:
            p = j["parent"]
            pos[k] = pos[p] + rot[p].apply(t)
            rot[k] = rot[p] * r
    sites = [pos[k] + rot[k].apply(np.tile(s, (values.shape[0], 1)))
             for k, j in enumerate(joints) for s in j["end_sites"]]
    return np.stack(pos + sites, axis=1), rot


def heading_local_points(joints, values):
    points, rot = world_points(joints, values)
    root = [k for k, j in enumerate(joints) if j["parent"] < 0][0]
    m = rot[root].as_matrix()  # frames x 3 x 3; columns are the rotated axes
    # Up = Y; floor axes a = Z, b = X (cyclic after Y). Average the heading estimates of both.
    va, vb = m[:, :, 2], m[:, :, 0]
    theta = np.arctan2(va[:, 0] - vb[:, 2], va[:, 2] + vb[:, 0])
    unturn = Rotation.from_euler("y", -theta)
    origin = points[:, root, :].copy()
    origin[:, 1] = 0.0
    centred = points - origin[:, None, :]
    out = np.stack([unturn.apply(centred[:, p, :]) for p in range(points.shape[1])], axis=1)
    return out.reshape(values.shape[0], -1)


def quaternion_features(joints, values, rows):
    local = local_transforms(joints, values)
    blocks = []
    for k, j in enumerate(joints):
        if j["parent"] < 0:
            continue
        q = local[k][1].as_quat()[rows]  # x, y, z, w
        q = np.concatenate([q[:, 3:], q[:, :3]], axis=1)  # w, x, y, z
        if q[0, 0] < 0:
            q[0] = -q[0]
        for r in range(1, len(q)):
            if np.dot(q[r], q[r - 1]) < 0:
                q[r] = -q[r]
        blocks.append(q)
    return np.concatenate(blocks, axis=1)


def map_inputs(path, first=None, end=None, stride=1):
    """X, D and the file frame indices of the samples, as `motionmap map` builds them."""
    joints, values, _ = parse_bvh(path)
    cloud = heading_local_points(joints, values)
    start = 0
    if first is None:
        steps = np.linalg.norm(np.diff(cloud[1:], axis=0), axis=1)
        if np.linalg.norm(cloud[0] - cloud[1]) > 10 * np.median(steps):
            start = 1
    else:
        start = first
    rows = np.arange(start, values.shape[0] if end is None else end, stride)
    X = quaternion_features(joints, values, rows)
    P = cloud[rows]
    D = cdist(P, P)
    return X, D, rows
