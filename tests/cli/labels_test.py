#!/usr/bin/env python3
"""End-to-end tests of labels in the `motionmap` tool (docs/labels.md) on the 12 labelled Bandai
takes in ../shared/data/bandai (never copied; a faster copy of each, every other frame, is written
to the scratch folder to make a library of 24 clips): --labels-from-name and --labels (CSV, JSON)
and their errors, the label columns of the CSV, the map file's labels shown by `info`, --color-by
with a legend, and the label accuracy of --metrics against scikit-learn's k-NN classifier.

usage: labels_test.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import csv
import json
import os
import re
import sys

try:
    import h5py
    import numpy as np
    from sklearn.neighbors import KNeighborsClassifier, NearestNeighbors
except ImportError:  # scripts/install-deps.sh installs python3-h5py and python3-sklearn
    h5py = None

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from clirun import DATA, main, run, test, tmp  # noqa: E402

BANDAI = os.path.join(DATA, "bandai")
TEMPLATE = "{action}_{style}_{take}"


def takes():
    """The 12 Bandai takes, sorted (None when they are not all there)."""
    if not os.path.isdir(BANDAI):
        return None
    names = sorted(n for n in os.listdir(BANDAI) if n.endswith(".bvh"))
    return [os.path.join(BANDAI, n) for n in names] if len(names) == 12 else None


def needs_takes():
    if takes() is None:
        print("  skipped: the 12 Bandai takes are not in " + BANDAI)
        return False
    return True


def needs_sklearn():
    if h5py is None:
        print("  skipped: h5py, numpy or scikit-learn is missing (python3-h5py, python3-sklearn)")
        return False
    return True


def read_csv(path):
    """(comment lines, header, rows) of a map CSV."""
    comments, rows = [], []
    with open(path, newline="", encoding="utf-8") as f:
        lines = [line for line in f]
    comments = [line.rstrip("\n") for line in lines if line.startswith("#")]
    body = [line for line in lines if not line.startswith("#")]
    reader = csv.reader(body)
    header = next(reader)
    rows = list(reader)
    return comments, header, rows


def faster_copy(path, folder):
    """The take at `path` played twice as fast (every other frame), written under `folder` as
    fast-NAME: a clip of its own with the take's labels (the template matches the end)."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    motion = lines.index("MOTION")
    frames = lines[motion + 3:]
    kept = frames[::2]
    time = float(lines[motion + 2].split(":")[1]) * 2
    out = lines[:motion + 1] + [f"Frames: {len(kept)}", f"Frame Time: {time:.7f}"] + kept
    target = os.path.join(folder, "fast-" + os.path.basename(path))
    with open(target, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")
    return target


def library():
    """The 12 takes and their 12 faster copies (made once)."""
    folder = tmp("library")
    if not os.path.isdir(folder):
        os.makedirs(folder)
        for path in takes():
            faster_copy(path, folder)
    return takes() + sorted(os.path.join(folder, n) for n in os.listdir(folder))


def label_of(path, field):
    """A label read back from a Bandai file name, as the template reads it."""
    action, style, take = os.path.splitext(os.path.basename(path))[0].split("_")[-3:]
    return {"action": action, "style": style, "take": take}[field]


def vote(neighbor_labels):
    """The label a vote of neighbours (nearest first) gives, a tie to the tied label whose
    nearest voter is nearest (docs/labels.md)."""
    counts = {}
    for label in neighbor_labels:
        counts[label] = counts.get(label, 0) + 1
    best = max(counts.values())
    return next(label for label in neighbor_labels if counts[label] == best)


def knn_accuracy(points, labels, clips, k=10):
    """The reference: for each clip, scikit-learn's brute-force NearestNeighbors, fitted on the
    other clips' frames, finds each of the clip's frames' k nearest; their vote (as documented)
    against the frame's label. Also scikit-learn's own KNeighborsClassifier, which breaks a tied
    vote by the smaller label: (ours, scikit-learn's classifier)."""
    labels = np.asarray(labels)
    clips = np.asarray(clips)
    right = classifier_right = 0
    for c in np.unique(clips):
        query, others = clips == c, clips != c
        nn = NearestNeighbors(n_neighbors=k, algorithm="brute").fit(points[others])
        _, index = nn.kneighbors(points[query])
        voters = labels[others][index]
        right += sum(vote(list(v)) == t for v, t in zip(voters, labels[query]))
        model = KNeighborsClassifier(n_neighbors=k, algorithm="brute")
        model.fit(points[others], labels[others])
        classifier_right += int((model.predict(points[query]) == labels[query]).sum())
    return right / len(labels), classifier_right / len(labels)


@test
def help_describes_the_label_options():
    for command in ("map", "figure"):
        code, out, _ = run(command, "--help")
        assert code == 0
        for word in ("--labels-from-name", "--labels", "--color-by", "{action}_{style}_{take}",
                     "re:"):
            assert word in out, (command, word)


@test
def labels_from_the_file_names_become_csv_columns():
    if not needs_takes():
        return
    out = tmp("names.csv")
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels-from-name", TEMPLATE, "-o", out)
    assert code == 0, err
    _, header, rows = read_csv(out)
    assert header == ["clip", "frame", "x", "y", "action", "style", "take"], header
    assert len(rows) == 2040
    paths = takes()
    for row in rows:
        clip = paths[int(row[0])]
        assert row[4:] == [label_of(clip, "action"), label_of(clip, "style"), "001"], row
    # The same with a regular expression of named groups, in either spelling.
    out2 = tmp("regex.csv")
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "-o", out2, "--labels-from-name",
                       r"re:_(?P<action>[a-z]+)_(?<style>[a-z]+)_\d+$")
    assert code == 0, err
    _, header2, rows2 = read_csv(out2)
    assert header2 == ["clip", "frame", "x", "y", "action", "style"]
    assert [r[4:6] for r in rows2] == [r[4:6] for r in rows]


@test
def a_name_that_does_not_match_is_an_error_naming_the_file_and_the_template():
    if not needs_takes():
        return
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels-from-name",
                       "{action}_{style}_{take}_{extra}_{more}")
    assert code == 1, err
    assert "dataset-1_bow_normal_001.bvh: error: the file name 'dataset-1_bow_normal_001' " \
           "does not match the label pattern '{action}_{style}_{take}_{extra}_{more}'" in err, err
    # A pattern that is not one is a usage error.
    code, _, err = run("map", BANDAI, "--labels-from-name", "{action")
    assert code == 2 and "'{' without '}'" in err, err


@test
def label_files_in_csv_and_json_with_spans_and_their_errors():
    if not needs_takes():
        return
    labels = tmp("spans.csv")
    with open(labels, "w", encoding="utf-8") as f:
        f.write("clip,start,end,phase\n"
                "dataset-1_walk_angry_001,0,49,start\n"
                "dataset-1_walk_angry_001.bvh,50,99,\"middle, steady\"\n")
    out = tmp("spans_map.csv")
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels", labels, "-o", out)
    assert code == 0, err
    assert "11 of 12 clips have no labels" in err, err
    _, header, rows = read_csv(out)
    assert header[-1] == "phase"
    walk = takes().index(os.path.join(BANDAI, "dataset-1_walk_angry_001.bvh"))
    phases = {(int(r[0]), int(r[1])): r[-1] for r in rows}
    assert phases[(walk, 10)] == "start" and phases[(walk, 60)] == "middle, steady"
    assert phases[(walk, 120)] == "" and phases[(0, 10)] == ""
    # JSON, with the file names' labels: the file's come after.
    js = tmp("labels.json")
    with open(js, "w", encoding="utf-8") as f:
        json.dump({"dataset-1_run_old_001": {"action": "jog", "mood": "calm"}}, f)
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels-from-name", TEMPLATE,
                       "--labels", js, "-o", out)
    assert code == 0, err
    _, header, rows = read_csv(out)
    assert header[4:] == ["action", "style", "take", "mood"]
    run_old = takes().index(os.path.join(BANDAI, "dataset-1_run_old_001.bvh"))
    assert {r[4] for r in rows if int(r[0]) == run_old} == {"jog"}
    assert {r[7] for r in rows if int(r[0]) == run_old} == {"calm"}
    # Every bad input: file, line, column and what was expected.
    cases = [
        ("clip,action\nnope,walk\n", "bad.csv:2:1: error: unknown clip 'nope'"),
        ("clip,start,end,action\ndataset-1_bow_old_001,5,2,bow\n",
         "bad.csv:2:23: error: start 5 is after end 2"),
        ("clip,start,end,action\ndataset-1_bow_old_001,0,9999,bow\n",
         "bad.csv:2:23: error: frame 9999 is beyond clip 'dataset-1_bow_old_001.bvh', whose "
         "frames are 0-"),
        ("clip,action,action\n", "bad.csv:1:13: error: duplicate column 'action'"),
        ("clip,start,end,action\ndataset-1_bow_old_001,x,3,bow\n",
         "bad.csv:2:23: error: expected the start frame (an integer ≥ 0), found 'x'"),
        ("", "bad.csv:1:1: error: the file is empty"),
        ("clip,action\ndataset-1_bow_old_001,b\xe9\n",
         "bad.csv:2:23: error: expected a label value, found a label value that is not valid "
         "UTF-8"),
    ]
    bad = tmp("bad.csv")
    for text, expected in cases:
        with open(bad, "wb") as f:
            f.write(text.encode("latin-1"))
        code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels", bad)
        assert code == 1, (text, err)
        assert (bad + ":" + expected[len("bad.csv:"):]) in err, (expected, err)
        err.encode("utf-8")  # the message is text


@test
def metrics_give_the_label_accuracy_as_scikit_learn_computes_it():
    if not needs_takes() or not needs_sklearn():
        return
    paths = library()
    listing = tmp("library.txt")
    with open(listing, "w", encoding="utf-8") as f:
        f.write("\n".join(paths) + "\n")
    for method in ("pca", "isomap"):
        out = tmp(f"metrics_{method}.csv")
        code, stdout, err = run("map", "@" + listing, "-m", method, "-q", "--metrics",
                                "--labels-from-name", TEMPLATE, "-o", out)
        assert code == 0, err
        comments, header, rows = read_csv(out)
        line = [c for c in comments if c.startswith("# label accuracy")]
        assert len(line) == 1, comments
        found = dict(re.findall(r"label_accuracy\[(\w+)\]=([0-9.]+)/", line[0]))
        assert set(found) == {"action", "style"}, line  # take is 001 everywhere: not measured
        assert "label accuracy" in stdout and "features" in stdout, stdout
        Y = np.array([[float(r[2]), float(r[3])] for r in rows])
        clips = [int(r[0]) for r in rows]
        for label, column in (("action", 4), ("style", 5)):
            reference, classifier = knn_accuracy(Y, [r[column] for r in rows], clips)
            # The neighbours of frames at equal distances may come in another order (the
            # faster copies repeat every other frame of their takes): hence the tolerance.
            assert abs(float(found[label]) - reference) <= 0.01, (method, label, found, reference)
            print(f"  {method} {label}: motionmap {found[label]}, scikit-learn neighbours "
                  f"{reference:.4f} (its classifier, ties to the smaller label: "
                  f"{classifier:.4f})")


@test
def saved_labels_are_shown_by_info_and_a_damaged_label_dataset_is_an_error():
    if not needs_takes():
        return
    h5 = tmp("labels.mmap.h5")
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels-from-name", TEMPLATE,
                       "--save", h5, "-o", tmp("saved.csv"))
    assert code == 0, err
    code, out, err = run("info", h5)
    assert code == 0, err
    assert "map file, pca, 2 dims, 2040 frames of 12 clips" in out, out
    assert "action (5 values): bow " in out and "take (1 value): 001 2040" in out, out
    code, out, err = run("info", h5, "--json")
    assert code == 0, err
    info = json.loads(out)
    actions = info["map"]["labels"]["action"]
    assert set(actions) == {"bow", "dash", "punch", "run", "walk"}
    assert sum(actions.values()) == 2040
    assert info["map"]["labels"]["take"] == {"001": 2040}
    # The counts are the frames of each action's takes.
    _, _, rows = read_csv(tmp("saved.csv"))
    for action, count in actions.items():
        assert count == sum(1 for r in rows if r[4] == action), action
    if h5py is None:
        print("  skipped the damaged file: h5py is missing")
        return
    with h5py.File(h5, "r+") as f:
        codes = f["/labels/0/codes"]
        values = codes[...]
        values[7] = (values[7] + 1) % len(f["/labels/0/values"])
        codes[...] = values
    code, _, err = run("info", h5)
    assert code == 1, err
    assert h5 + ": error: /labels/0/codes is damaged: the checksum of its values is" in err, err
    code, _, err = run("map", takes()[0], "-q", "--onto", h5)
    assert code == 1 and "/labels/0/codes is damaged" in err, err


@test
def color_by_a_label_draws_a_legend_and_bad_names_are_usage_errors():
    if not needs_takes():
        return
    png = tmp("by_action.png")
    code, _, err = run("map", BANDAI, "-m", "isomap", "-q", "--labels-from-name", TEMPLATE,
                       "--color-by", "action", "--plot", png, "-o", tmp("plot.csv"))
    assert code == 0, err
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    for color_by in ("clip", "time", "style"):
        code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels-from-name", TEMPLATE,
                           "--color-by", color_by, "--plot", tmp(color_by + ".svg"), "-o",
                           tmp("p.csv"))
        assert code == 0, (color_by, err)
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--labels-from-name", TEMPLATE,
                       "--color-by", "mood", "--plot", tmp("x.png"))
    assert code == 2 and "no label named 'mood'; the labels are action, style, take" in err, err
    code, _, err = run("map", BANDAI, "-m", "pca", "-q", "--color-by", "action", "--plot",
                       tmp("x.png"))
    assert code == 2 and "give --labels-from-name or --labels" in err, err
    # More values than colours: the 11 most frequent coloured, the rest grey as "other".
    listing = tmp("library_plot.txt")
    with open(listing, "w", encoding="utf-8") as f:
        f.write("\n".join(library()) + "\n")
    code, _, err = run("map", "@" + listing, "-m", "pca", "-q", "--labels-from-name",
                       "re:^(?P<name>.+)$", "--color-by", "name", "--plot", tmp("names.png"),
                       "-o", tmp("names24.csv"))
    assert code == 0, err
    assert "note: label 'name' has 24 values; the plot colours the 11 most frequent and shows " \
           "the other 13 in grey as 'other'" in err, err
    # figure: every panel coloured, the accuracy per method in the table.
    fig = tmp("figure.png")
    code, out, err = run("figure", BANDAI, "-q", "--labels-from-name", TEMPLATE, "--color-by",
                         "action", "-o", fig, "--panel-size", "200")
    assert code == 0, err
    assert "acc[action]" in out and "acc[style]" in out, out
    assert "label accuracy of action in the feature space" in out, out


if __name__ == "__main__":
    sys.exit(main())
