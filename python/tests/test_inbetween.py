"""In-betweening from Python: motionmap.inbetween hits every key frame exactly (the clips' own
rotations and root translations, in world placement), places a frame that is not a sample of the
map, keeps every frame's map point in the valid region, counts frames as asked, warns of keys
further apart than the clips walk in the time given (or leaves later keys' roots free), takes a
map clip's file name for its path, and says what is wrong with a bad key."""
import numpy as np
import pytest

import motionmap


def same_rotations(a, b, atol):
    np.testing.assert_allclose(np.abs(np.sum(a * b, axis=-1)), 1.0, atol=atol)


def test_keys_are_hit_exactly(golf):
    est = motionmap.Isomap(stride=2).fit(golf)
    clip = motionmap.load(golf)
    # 40 and 200 are samples (stride 2 from frame 1: the T-pose is left out) or not: either way.
    keys = [(golf, 41), (golf, 200), (clip, 300)]
    for kind in ("clips", "grid"):
        motion, route = motionmap.inbetween(est, keys, frames_between=20, route=kind)
        assert isinstance(motion, motionmap.Clip) and motion.num_frames == 43
        assert route["key_frames"] == [0, 21, 42]
        assert route["points"].shape == (43, 2)
        assert all(route["valid"])
        assert len(route["routes"]) == 2 and route["routes"][0].shape[1] == 2
        for k, f in zip(route["key_frames"], (41, 200, 300)):
            same_rotations(motion.rotations[k], clip.rotations[f], 1e-9)
            np.testing.assert_allclose(motion.translations[k, 0], clip.translations[f, 0],
                                       rtol=1e-9, atol=1e-9)


def test_timing(golf):
    est = motionmap.Isomap().fit(golf)
    motion, route = motionmap.inbetween(est, [(golf, 50), (golf, 150)], times=[0.0, 0.5])
    assert motion.num_frames == 61 and route["key_frames"] == [0, 60]
    motion, route = motionmap.inbetween(est, [(golf, 50), (golf, 150)])
    assert motion.num_frames == route["key_frames"][1] + 1 > 2
    xy = est.embedding_[[10, 90]]
    motion, route = motionmap.inbetween(est, [tuple(xy[0]), tuple(xy[1])], frames_between=4)
    assert motion.num_frames == 6
    np.testing.assert_array_equal(route["points"][[0, -1]], xy)


def test_keys_further_apart_than_the_clips_walk_in_the_time_are_noted():
    """Each key's root stands where it stood in its clip: keys of two takes captured in different
    places, 5 frames apart, make the root glide, and the clip's warnings say so."""
    import os

    import conftest

    walk, bow = (os.path.join(conftest.DATA, "bandai", f"dataset-1_{name}_001.bvh")
                 for name in ("walk_angry", "bow_normal"))
    if not (os.path.exists(walk) and os.path.exists(bow)):
        pytest.skip("the Bandai takes are absent from the shared data")
    est = motionmap.Isomap(stride=2).fit([walk, bow])
    motion, _ = motionmap.inbetween(est, [(walk, 20), (bow, 40)], frames_between=5)
    notes = [w for w in motion.warnings if "apart (each where it stood in its clip)" in w]
    assert len(notes) == 1 and "the feet slide" in notes[0], motion.warnings
    motion, _ = motionmap.inbetween(est, [(walk, 20), (bow, 40)])
    assert not [w for w in motion.warnings if "apart (each where it stood" in w], motion.warnings
    # With free roots only the first key's root is placed: the bow's pose is hit, its root stands
    # where the clips carry it, and nothing glides.
    motion, route = motionmap.inbetween(est, [(walk, 20), (bow, 40)], frames_between=5,
                                        free_roots=True)
    assert not [w for w in motion.warnings if "glide" in w or "apart" in w], motion.warnings
    bow_clip = motionmap.load(bow)
    last = route["key_frames"][-1]
    same_rotations(motion.rotations[last, 2:], bow_clip.rotations[40, 2:], 1e-9)
    assert np.linalg.norm(motion.translations[last, 1] - bow_clip.translations[40, 1]) > 50.0


def test_a_key_may_name_a_clip_of_the_map(golf, tmp_path):
    """A clip path that is no file names the map's clip whose path ends with it, as in the CLI."""
    import os

    est = motionmap.Isomap(stride=2).fit(golf)
    name = os.path.basename(golf)
    by_path, _ = motionmap.inbetween(est, [(golf, 41), (golf, 200)], frames_between=10)
    by_name, _ = motionmap.inbetween(est, [(name, 41), (golf, 200)], frames_between=10)
    np.testing.assert_array_equal(by_name.rotations, by_path.rotations)
    with pytest.raises(motionmap.Error, match=r"keys\[0\]: no such clip file 'elsewhere.bvh', and "
                                              r"no clip of the map is named so \(its clip: 64_08.bvh\)"):
        motionmap.inbetween(est, [("elsewhere.bvh", 41), (golf, 200)])
    # A folder is no clip file: looked for among the map's clips by name, as the CLI does.
    folder = os.path.dirname(golf)
    with pytest.raises(motionmap.Error, match=r"keys\[0\]: no such clip file '.*', and no clip of "
                                              r"the map is named so"):
        motionmap.inbetween(est, [(folder, 41), (golf, 200)])


def test_bad_keys(golf, other):
    est = motionmap.Isomap().fit(golf)
    with pytest.raises(motionmap.Error, match="frame 365 is out of range: .* has 365 frames, 0 to 364"):
        motionmap.inbetween(est, [(golf, 10), (golf, 365)])
    with pytest.raises(motionmap.Error, match="another skeleton"):
        motionmap.inbetween(est, [(golf, 10), (other, 5)])
    with pytest.raises(motionmap.Error, match="a key is"):
        motionmap.inbetween(est, [(golf, 10), "x"])
    with pytest.raises(motionmap.Error, match="'fast' is not a route"):
        motionmap.inbetween(est, [(golf, 10), (golf, 20)], route="fast")
    with pytest.raises(motionmap.Error, match="at least 2"):
        motionmap.inbetween(est, [(golf, 10)])
    with pytest.raises(motionmap.Error, match="fitted on an array"):
        motionmap.inbetween(motionmap.PCA().fit(np.eye(5)), [(0, 0), (1, 1)])


def test_lafan_protocol_benchmark_tiny_case():
    """bench/inbetween_lafan.py on one window, n = 5: the three methods side by side."""
    import os
    import subprocess
    import sys

    import conftest

    script = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "inbetween_lafan.py")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(motionmap.__file__))
    p = subprocess.run([sys.executable, script, "--data", conftest.DATA, "--tiny"],
                       capture_output=True, text=True, env=env, timeout=240)
    if p.returncode == 77:
        pytest.skip(p.stdout.strip())
    assert p.returncode == 0, p.stdout + p.stderr
    for name in ("=== L2Q ===", "=== L2P ===", "=== NPSS ===", "MotionMap", "Interp",
                 "Zero-vel", "windows per length: 1"):
        assert name in p.stdout, p.stdout
    rows = {line.split("|")[0].strip(): float(line.split("|")[1])
            for line in p.stdout.splitlines() if line.count("|") == 1 and "n " not in line}
    assert all(np.isfinite(v) for v in rows.values()), p.stdout


def test_random_key_pairs_benchmark_tiny_case():
    """bench/inbetween_pairs.py on 3 pairs: a table row each, roots placed and free and the
    captured frames about the keys, and the counts."""
    import os
    import subprocess
    import sys

    import conftest

    cli = os.environ.get("MOTIONMAP_CLI")
    if not cli:
        pytest.skip("MOTIONMAP_CLI is not set (ctest sets it)")
    script = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "inbetween_pairs.py")
    p = subprocess.run([sys.executable, script, "--data", conftest.DATA, "--motionmap", cli,
                        "--pairs", "3"], capture_output=True, text=True, timeout=240)
    if p.returncode == 77:
        pytest.skip(p.stdout.strip())
    assert p.returncode == 0, p.stdout + p.stderr
    rows = [line for line in p.stdout.splitlines() if "→" in line]
    assert len(rows) == 3 and all(line.count("cm/s") == 5 for line in rows), p.stdout
    assert "roots at every key: " in p.stdout and "free roots: " in p.stdout, p.stdout
    assert p.stdout.count(" of 3 skate more than their keys' clips") == 2, p.stdout
    # Skating more than the clips and than their frames about the keys is skating more than the
    # clips.
    for kind in ("roots at every key: ", "free roots: "):
        line = next(line for line in p.stdout.splitlines() if line.startswith(kind))
        more = int(line[len(kind):].split(" of ")[0])
        beyond = int(line.split("; ")[-1].split(" skate more than the clips' frames")[0])
        assert beyond <= more, line
    # Per timing, the pairs add up to the 3 drawn.
    by_timing = next(line for line in p.stdout.splitlines() if line.startswith("skating more by"))
    assert sum(int(part.split(" of ")[1]) for part in by_timing.split("; ")) == 3, by_timing


def test_lafan_protocol_benchmark_refuses_a_held_out_take_it_cannot_test():
    """bench/inbetween_lafan.py --held-out: a name that is no Bandai take, and a take too short
    for one test window (the 24-frame normal run), are refused with exit code 2 and the reason,
    before any map is made."""
    import os
    import subprocess
    import sys

    import conftest

    if not os.path.exists(os.path.join(conftest.DATA, "bandai", "dataset-1_run_normal_001.bvh")):
        pytest.skip("the Bandai clips are absent")
    script = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "inbetween_lafan.py")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(motionmap.__file__))
    for take, reason in (("nosuch.bvh", "nosuch.bvh is not a take in"),
                         ("dataset-1_run_normal_001.bvh",
                          "dataset-1_run_normal_001.bvh has 24 frames; a test window needs more "
                          "than 65")):
        p = subprocess.run([sys.executable, script, "--data", conftest.DATA, "--held-out", take],
                           capture_output=True, text=True, env=env, timeout=60)
        assert p.returncode == 2, p.stdout + p.stderr
        assert reason in p.stderr, p.stderr
        assert "library:" not in p.stdout, p.stdout


def test_a_walks_stances_stay_planted_through_the_keys_displacement():
    """Keys of a walk not in the map (the proud walk, 45 frames apart, on the map of the other
    11 Bandai takes): between keys the route walks another take, and the keys' poses are reached
    by a displacement map spread over each segment, which lifts a planted foot slowly towards a
    key's. The clean-up takes its contacts from the blend before that displacement, so the feet
    stand about as often as in the walk itself (0.44 of the transitions against its 0.42; with
    the contacts of the displaced motion 0.31: a foot crept forward at 0.3 m/s through a
    stance)."""
    import glob
    import os
    import sys

    import conftest

    folder = os.path.join(conftest.DATA, "bandai")
    held_out = os.path.join(folder, "dataset-1_walk_proud_001.bvh")
    if not os.path.exists(held_out):
        pytest.skip(f"{held_out} absent from the shared data")
    library = [p for p in sorted(glob.glob(os.path.join(folder, "*.bvh"))) if p != held_out]
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "bench"))
    from inbetween_lafan import fk

    est = motionmap.Isomap().fit(library)
    motion, _ = motionmap.inbetween(est, [(held_out, f) for f in (20, 66, 112, 158)],
                                    frames_between=45)

    def standing(clip):
        names = list(clip.skeleton.names)
        positions = fk(clip.rotations, clip.translations,
                       [int(p) for p in clip.skeleton.parents])[1]
        fractions = []
        for ankle in ("Foot_L", "Foot_R"):
            floor = positions[:, names.index(ankle)][:, [0, 2]]
            fractions.append(np.mean(np.linalg.norm(np.diff(floor, axis=0), axis=1) < 0.5))
        return np.mean(fractions)

    made, own = standing(motion), standing(motionmap.load(held_out))
    print(f"ankles standing: {made:.3f} of transitions, the walk's {own:.3f}")
    assert made >= 0.9 * own, (made, own)


def test_an_inbetween_between_actions_on_a_saved_map_moves_no_faster_than_its_clips(cli,
                                                                                      tmp_path):
    """The saved map of the 12 Bandai takes (`map --save`), keys of a walk, a dash and a bow
    (`inbetween --map`): the map's blender reads its clips on demand. Its routes priced their
    jumps by map distance alone, and the chain of jumps so priced moved a joint 71 cm in a frame
    where the dash's fastest moves 33 (the same keys in memory: 21); now a map this small (at most
    20 000 samples) has its jumps priced by their poses, as in memory, and a larger one prices
    them against the bridge (each key's clip played towards the middle) by their poses
    (tests/synth/inbetween_test.cpp, JumpsOnABlenderReadingItsClipsOnDemandArePricedByPoses)."""
    import glob
    import os
    import subprocess

    import conftest

    takes = sorted(glob.glob(os.path.join(conftest.DATA, "bandai", "*.bvh")))
    if len(takes) != 12:
        pytest.skip("the 12 Bandai takes are not all in the shared data")
    keyed = [(os.path.join(conftest.DATA, "bandai", f"dataset-1_{name}_001.bvh"), frame)
             for name, frame in (("walk_old", 50), ("dash_normal", 10), ("bow_old", 80))]
    h5 = tmp_path / "lib.mmap.h5"
    subprocess.run([cli, "map", *takes, "--save", str(h5), "-o", str(tmp_path / "lib.csv"),
                    "-q"], check=True, capture_output=True)
    out = tmp_path / "between.bvh"
    keys = ",".join(f"{path}:{frame}" for path, frame in keyed)
    subprocess.run([cli, "inbetween", "--map", str(h5), "--keys", keys, "-o", str(out)],
                   check=True, capture_output=True)

    def largest_step(clip):  # of any joint below the static joint_Root, in a frame
        p = clip.positions()[:, 1:]
        return np.linalg.norm(np.diff(p, axis=0), axis=2).max()

    made = largest_step(motionmap.load(str(out)))
    clips = max(largest_step(motionmap.load(path)) for path, _ in keyed)
    print(f"a joint's largest step {made:.1f} cm, the clips' {clips:.1f}")
    assert made <= clips, (made, clips)
