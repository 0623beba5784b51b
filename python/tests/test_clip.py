"""motionmap.load and Clip: the skeleton, rotations, translations, forward kinematics, info() as
`motionmap info --json` prints it, save() as BVH read back, and errors as motionmap.Error."""
import json
import os
import subprocess

import numpy as np
import pytest

import motionmap


def test_load_bvh_skeleton_and_motion(golf):
    clip = motionmap.load(golf)
    sk = clip.skeleton
    assert clip.path == golf
    assert len(sk.names) == sk.num_joints == len(sk)
    assert sk.parents[0] == -1 and all(p < j for j, p in enumerate(sk.parents))
    assert sk.offsets.shape == (sk.num_joints, 3)
    assert sk.channels[0][:3] == ["Xposition", "Yposition", "Zposition"]
    assert sk.find(sk.names[3]) == 3 and sk.find("no such joint") == -1
    assert clip.num_frames == 365 and len(clip) == 365
    q = clip.rotations
    assert q.shape == (365, sk.num_joints, 4) and q.dtype == np.float64
    np.testing.assert_allclose(np.linalg.norm(q, axis=2), 1.0, atol=1e-12)
    t = clip.translations
    assert t.shape == (365, sk.num_joints, 3)
    np.testing.assert_array_equal(clip.root_translations, t[:, sk.roots[0], :])
    # A joint without position channels keeps its rest offset.
    np.testing.assert_array_equal(t[:, 1, :], np.broadcast_to(sk.offsets[1], (365, 3)))


def test_positions_are_forward_kinematics(golf):
    clip = motionmap.load(golf)
    p = clip.positions()
    sk = clip.skeleton
    n_end = sum(len(e) for e in sk.end_sites)
    assert p.shape == (clip.num_frames, sk.num_joints + n_end, 3)
    assert p.flags.c_contiguous
    # The root's world position is its translation (its parent is the world).
    np.testing.assert_allclose(p[:, 0, :], clip.root_translations, atol=1e-9)
    # A child sits at its offset rotated by its parent's world rotation: the distance is kept.
    for j in range(1, sk.num_joints):
        dist = np.linalg.norm(p[:, j, :] - p[:, sk.parents[j], :], axis=1)
        np.testing.assert_allclose(dist, np.linalg.norm(sk.offsets[j]), rtol=1e-9, atol=1e-9)


def test_info_matches_the_cli(golf, cli):
    ours = motionmap.load(golf).info()
    out = subprocess.run([cli, "info", "--json", golf], capture_output=True, text=True,
                         check=True).stdout
    theirs = json.loads(out)
    assert set(ours) == set(theirs)
    for key in ("file", "joints", "roots", "root_names", "channels", "end_sites", "frames",
                "warnings"):
        assert ours[key] == theirs[key], key
    assert ours["frame_time"] == theirs["frame_time"]  # printed with 17 digits
    for key in ("fps", "duration"):
        assert ours[key] == pytest.approx(theirs[key], rel=1e-5)  # printed with 6 digits
    for end in ("min", "max"):
        np.testing.assert_allclose(ours["bounding_box"][end], theirs["bounding_box"][end],
                                   rtol=1e-5, atol=1e-4)


def test_save_round_trip(golf, tmp_path):
    clip = motionmap.load(golf)
    out = tmp_path / "copy.bvh"
    clip.save(out)
    back = motionmap.load(str(out))
    assert back.skeleton.names == clip.skeleton.names
    assert back.frame_time == clip.frame_time
    # Rotations go through Euler angles and back: equal up to sign and rounding.
    dots = np.abs(np.sum(back.rotations * clip.rotations, axis=2))
    np.testing.assert_allclose(dots, 1.0, atol=1e-9)
    np.testing.assert_allclose(back.positions(), clip.positions(), atol=1e-6)


def test_amc_with_asf_and_fps(amc):
    asf = os.path.join(os.path.dirname(amc), "02.asf")
    clip = motionmap.load(amc, asf=asf, fps=60)
    assert clip.frame_time == pytest.approx(1 / 60)
    default = motionmap.load(amc)  # the .asf beside it, 120 fps
    assert default.frame_time == pytest.approx(1 / 120)
    assert default.skeleton.names == clip.skeleton.names


def test_errors_are_motionmap_errors_with_the_cli_message(tmp_path, cli):
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n")
    with pytest.raises(motionmap.Error) as e:
        motionmap.load(str(bad))
    assert isinstance(e.value, ValueError)
    message = str(e.value)
    assert message.startswith(f"{bad}:4:")
    assert ": error: " in message
    p = subprocess.run([cli, "info", str(bad)], capture_output=True, text=True)
    assert p.stderr.strip() .splitlines()[0] == "motionmap: " + message
    with pytest.raises(motionmap.Error, match="no-such.bvh"):
        motionmap.load(str(tmp_path / "no-such.bvh"))
    with pytest.raises(motionmap.Error, match="fps"):
        motionmap.load(str(bad), fps=-1)
