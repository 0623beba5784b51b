"""Labels in Python (docs/labels.md): labels_ as a dict of per-frame arrays (a DataFrame's
columns), kept by write_map/read_map and pickling, and label_accuracy() checked against an
independent reference — scikit-learn's k-NN classifier, fitted on the other clips' frames — in the
map and in the feature space (the pose distances D), on the 12 Bandai takes."""
import os
import pickle

import numpy as np
import pytest

import motionmap
from conftest import DATA

TEMPLATE = "{action}_{style}_{take}"


@pytest.fixture
def bandai():
    folder = os.path.join(DATA, "bandai")
    names = sorted(n for n in os.listdir(folder)) if os.path.isdir(folder) else []
    paths = [os.path.join(folder, n) for n in names if n.endswith(".bvh")]
    if len(paths) != 12:
        pytest.skip(f"the 12 Bandai takes are not in {folder}")
    return paths


def vote(neighbor_labels):
    """A vote of neighbours (nearest first): the most votes, a tie to the tied label whose
    nearest voter is nearest (docs/labels.md)."""
    counts = {}
    for label in neighbor_labels:
        counts[label] = counts.get(label, 0) + 1
    best = max(counts.values())
    return next(label for label in neighbor_labels if counts[label] == best)


def reference_accuracy(labels, clips, D, k=10):
    """For each clip: scikit-learn's NearestNeighbors on the other clips' frames, by the
    precomputed distances D (#frames by #frames), finds the clip's frames' k nearest; their vote
    against the frame's label. Also scikit-learn's KNeighborsClassifier (a tied vote to the
    smaller label). Returns (the fraction right, the classifier's)."""
    neighbors = pytest.importorskip("sklearn.neighbors")
    right = classifier_right = 0
    for c in np.unique(clips):
        query, others = clips == c, clips != c
        nn = neighbors.NearestNeighbors(n_neighbors=k, metric="precomputed")
        nn.fit(D[np.ix_(others, others)])
        _, index = nn.kneighbors(D[np.ix_(query, others)])
        voters = labels[others][index]
        right += sum(vote(list(v)) == t for v, t in zip(voters, labels[query]))
        model = neighbors.KNeighborsClassifier(n_neighbors=k, metric="precomputed")
        model.fit(D[np.ix_(others, others)], labels[others])
        classifier_right += int((model.predict(D[np.ix_(query, others)]) == labels[query]).sum())
    return right / len(labels), classifier_right / len(labels)


def test_labels_are_per_frame_arrays_kept_in_map_files_and_pickles(bandai, tmp_path):
    est = motionmap.PCA().fit(bandai, labels_from_name=TEMPLATE)
    labels = est.labels_
    assert list(labels) == ["action", "style", "take"]
    n = len(est.embedding_)
    for values in labels.values():
        assert values.shape == (n,) and values.dtype == object
    clips = est.clip_of_
    for i in (0, n // 2, n - 1):
        stem = os.path.splitext(os.path.basename(bandai[clips[i]]))[0]
        assert [labels["action"][i], labels["style"][i], labels["take"][i]] == stem.split("_")[1:]
    path = tmp_path / "labelled.mmap.h5"
    motionmap.write_map(est, path)
    back = motionmap.read_map(path)
    for name, values in labels.items():
        np.testing.assert_array_equal(back.labels_[name], values)
    thawed = pickle.loads(pickle.dumps(est))
    np.testing.assert_array_equal(thawed.labels_["style"], labels["style"])
    # Without labels: an empty dict.
    assert motionmap.PCA().fit(bandai[:2]).labels_ == {}
    # A label file's spans; a bad one raises motionmap.Error naming the line.
    spans = tmp_path / "spans.csv"
    spans.write_text("clip,start,end,phase\ndataset-1_bow_old_001,0,9,rise\n", encoding="utf-8")
    est2 = motionmap.PCA().fit(bandai, labels=spans)
    phases = est2.labels_["phase"]
    bow_old = bandai.index(os.path.join(os.path.dirname(bandai[0]), "dataset-1_bow_old_001.bvh"))
    spanned = (est2.clip_of_ == bow_old) & (est2.frame_of_ <= 9)
    assert spanned.sum() > 0 and (phases == "rise").sum() == spanned.sum()
    assert set(phases[~spanned]) == {""}
    spans.write_text("clip,action\nnope,walk\n", encoding="utf-8")
    with pytest.raises(motionmap.Error, match=r"spans.csv:2:1: error: unknown clip 'nope'"):
        motionmap.PCA().fit(bandai, labels=spans)


@pytest.mark.parametrize("cls", [motionmap.PCA, motionmap.Isomap])
def test_label_accuracy_equals_scikit_learns_k_nn_vote_among_other_clips(bandai, cls):
    est = cls().fit(bandai, labels_from_name=TEMPLATE)
    accuracy = est.label_accuracy()
    assert set(accuracy) == {"action", "style"}  # take is 001 everywhere: not measured
    clips = est.clip_of_
    _, D = motionmap.features(bandai, return_distances=True)
    Y = est.embedding_
    DY = np.sqrt(((Y[:, None, :] - Y[None, :, :]) ** 2).sum(-1))
    for name in ("action", "style"):
        labels = est.labels_[name]
        assert accuracy[name]["queries"] == len(labels) and accuracy[name]["k"] == 10
        # scikit-learn's neighbours, voted as documented: the same within 0.01 (frames at equal
        # distances may come in another order). Its classifier breaks a tied vote by the smaller
        # label instead: within 0.03.
        features, features_classifier = reference_accuracy(labels, clips, D)
        on_map, map_classifier = reference_accuracy(labels, clips, DY)
        assert abs(accuracy[name]["features"] - features) <= 0.01, (name, accuracy, features)
        assert abs(accuracy[name]["map"] - on_map) <= 0.01, (name, accuracy, on_map)
        assert abs(accuracy[name]["features"] - features_classifier) <= 0.03
        assert abs(accuracy[name]["map"] - map_classifier) <= 0.03
