"""Poses and motions from map points: inverse_transform at a sample's map point gives that frame's
pose (the blends are exact at samples), the same after read_map (the clips reloaded from their
paths), and synthesize along the clip's own map trajectory reproduces its joint rotations; the
CLI's `pose --at` writes the same pose."""
import json
import subprocess

import numpy as np
import pytest

import motionmap


def same_rotations(a, b, atol):
    np.testing.assert_allclose(np.abs(np.sum(a * b, axis=-1)), 1.0, atol=atol)


def test_inverse_transform_is_exact_at_samples(golf, tmp_path):
    est = motionmap.Isomap().fit(golf)
    clip = motionmap.load(golf)
    rows = [5, 100, 250]
    poses = est.inverse_transform(est.embedding_[rows])
    assert isinstance(poses, motionmap.Clip) and poses.num_frames == 3
    assert poses.skeleton.names == clip.skeleton.names
    frames = est.frame_of_[rows]
    # Every joint but the root (whose heading is removed) has the sample frame's rotation.
    same_rotations(poses.rotations[:, 1:], clip.rotations[frames, 1:], 1e-9)
    path = tmp_path / "m.mmap.h5"
    motionmap.write_map(est, path)
    again = motionmap.read_map(path).inverse_transform(est.embedding_[rows])
    np.testing.assert_array_equal(again.rotations, poses.rotations)
    with pytest.raises(motionmap.Error, match="blend: unknown name"):
        est.inverse_transform(est.embedding_[:1], blend="nearest")
    with pytest.raises(motionmap.Error, match="by 2"):
        est.inverse_transform(np.zeros((2, 3)))
    with pytest.raises(motionmap.Error, match="fitted on an array"):
        motionmap.PCA().fit(np.eye(5)).inverse_transform(np.zeros((1, 2)))


def test_pose_matches_the_cli(golf, cli, tmp_path):
    est = motionmap.Isomap().fit(golf)
    at = est.embedding_[40] * 0.5 + est.embedding_[41] * 0.5
    out = tmp_path / "pose.bvh"
    subprocess.run([cli, "pose", golf, f"--at={at[0]!r},{at[1]!r}", "-o", str(out)], check=True,
                   capture_output=True)
    theirs = motionmap.load(str(out))
    ours = est.inverse_transform(at[None, :])
    # The CLI writes BVH (Euler angles, shortest round-trip numbers): equal to rounding.
    same_rotations(ours.rotations, theirs.rotations, 1e-9)


def test_synthesize_retraces_the_clip(golf, tmp_path):
    est = motionmap.Isomap().fit(golf)
    clip = motionmap.load(golf)
    frames = est.frame_of_
    times = frames * clip.frame_time
    motion = motionmap.synthesize(est, est.embedding_, times, clean_feet=False)
    assert motion.frame_time == pytest.approx(clip.frame_time)
    n = min(motion.num_frames, len(frames))
    same_rotations(motion.rotations[:n, 1:], clip.rotations[frames[:n], 1:], 1e-6)
    motion.save(tmp_path / "new.bvh")
    assert motionmap.load(str(tmp_path / "new.bvh")).num_frames == motion.num_frames
    with pytest.raises(motionmap.Error, match="times"):
        motionmap.synthesize(est, est.embedding_[:3], [0.0, 1.0])


def test_edit_path_keeps_the_take_outside_its_window(golf):
    est = motionmap.Isomap().fit(golf)
    sketch = est.embedding_[::30]
    times = est.frame_of_[::30] / 120.0
    take = motionmap.synthesize(est, sketch, times, smooth=0.05)
    moved = sketch.copy()
    moved[5] += 0.3 * (sketch[6] - sketch[5])
    edited, window = motionmap.edit_path(est, moved, times, previous_xy=sketch,
                                         previous_times=times, smooth=0.05)
    first, end = window["first"], window["end"]
    assert edited.num_frames == take.num_frames and not window["whole"]
    assert 0 < first <= window["blend_first"] < window["blend_end"] <= end < take.num_frames
    # Outside the window: the take, bit for bit; inside, something changed.
    np.testing.assert_array_equal(edited.rotations[:first], take.rotations[:first])
    np.testing.assert_array_equal(edited.rotations[end:], take.rotations[end:])
    np.testing.assert_array_equal(edited.translations[:first], take.translations[:first])
    np.testing.assert_array_equal(edited.translations[end:], take.translations[end:])
    assert not np.array_equal(edited.rotations[first:end], take.rotations[first:end])
    assert window["feet_frames_changed"] >= 0
    # The same path: nothing re-made.
    same, window = motionmap.edit_path(est, sketch, times, previous_xy=sketch,
                                       previous_times=times, smooth=0.05)
    assert window["first"] == window["end"]
    np.testing.assert_array_equal(same.rotations, take.rotations)
    # An untimed path whose first point moved reaches every frame: synthesized whole.
    untimed = sketch.copy()
    untimed[0] += 0.5 * (sketch[1] - sketch[0])
    whole, window = motionmap.edit_path(est, untimed, previous_xy=sketch)
    assert window["whole"] and window["first"] == 0 and window["end"] == whole.num_frames
    np.testing.assert_array_equal(whole.rotations, motionmap.synthesize(est, untimed).rotations)
    with pytest.raises(motionmap.Error, match="previous_times: 2 times for"):
        motionmap.edit_path(est, moved, times, previous_xy=sketch, previous_times=[0.0, 1.0])
    with pytest.raises(motionmap.Error, match="previous path: "):
        motionmap.edit_path(est, moved, times, previous_xy=sketch, previous_times=times[::-1])
    with pytest.raises(TypeError):
        motionmap.edit_path(est, moved, times)  # previous_xy is required
    with pytest.raises(motionmap.Error, match="fitted on an array"):
        motionmap.edit_path(motionmap.PCA().fit(np.eye(5)), moved, previous_xy=sketch)


def test_a_stalled_gait_is_routed_and_said(cli, tmp_path):
    # The tired walk drawn 30 % of the way to the old one, at its own timing: beside both curves
    # the blend's legs would stall mid-stride (a foot held up for 3 s); the clips' own frames play
    # there and the clip's warnings say so. Its feet come down as the capture's do (`info
    # --skating`: how long a foot stays up).
    from conftest import data_path
    tired_path = data_path("bandai/dataset-1_walk_tired_001.bvh")
    tired = motionmap.load(tired_path)
    old = motionmap.load(data_path("bandai/dataset-1_walk_old_001.bvh"))
    est = motionmap.PCA().fit([tired, old])
    a, b = est.embedding_[:tired.num_frames], est.embedding_[tired.num_frames:]
    pick = np.rint(np.arange(tired.num_frames) / (tired.num_frames - 1) * (len(b) - 1))
    path = 0.7 * a + 0.3 * b[pick.astype(int)]
    clip = motionmap.synthesize(est, path, np.arange(tired.num_frames) * tired.frame_time)
    assert any("held its legs mid-stride" in w for w in clip.warnings), clip.warnings

    clip.save(str(tmp_path / "sketch.bvh"))

    def longest_up(path):
        out = subprocess.run([cli, "info", "--json", "--skating", str(path)], check=True,
                             capture_output=True, text=True).stdout
        return json.loads(out)["skating"]["longest_raised_s"]
    assert longest_up(tmp_path / "sketch.bvh") <= longest_up(tired_path) + 0.5
