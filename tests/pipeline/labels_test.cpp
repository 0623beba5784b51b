// Labels: file-name patterns, label files (CSV, JSON) and their errors, labels per sample, the
// k-NN label vote and the label accuracy of a map, on the 12 Bandai takes.
#include "motionmap/pipeline/labels.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/core/metric.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/metrics.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/clip_map.h"
#include "support/test_data.h"

namespace motionmap::pipeline {
namespace {

std::vector<std::string> bandai_paths() {
  std::vector<std::string> paths;
  for (const std::string& p : test::shared_files_with_extension(".bvh")) {
    if (p.find("/bandai/") != std::string::npos) paths.push_back(p);
  }
  return paths;
}

// The message of what `f` throws (empty when it throws nothing).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

bool valid_utf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const int extra = c < 0x80 ? 0 : c >= 0xf0 ? 3 : c >= 0xe0 ? 2 : c >= 0xc2 ? 1 : -1;
    if (extra < 0 || i + std::size_t(extra) >= s.size() + (extra == 0 ? 1 : 0)) return false;
    for (int k = 1; k <= extra; ++k) {
      if ((static_cast<unsigned char>(s[i + std::size_t(k)]) & 0xc0) != 0x80) return false;
    }
    i += std::size_t(extra) + 1;
  }
  return true;
}

TEST(NamePattern, ATemplateMatchesTheEndOfTheNameSoAPrefixIsSkipped) {
  const NamePattern pattern("{action}_{style}_{take}");
  EXPECT_EQ(pattern.names(), (std::vector<std::string>{"action", "style", "take"}));
  const auto values = pattern.match("/data/bandai/dataset-1_walk_angry_001.bvh");
  ASSERT_TRUE(values);
  EXPECT_EQ(*values, (std::vector<std::string>{"walk", "angry", "001"}));
  // Anchored at the start, the prefix is a field of its own; "{_}" captures and drops.
  const NamePattern anchored("^dataset-{set}_{action}_{_}_{take}");
  EXPECT_EQ(anchored.names(), (std::vector<std::string>{"set", "action", "take"}));
  EXPECT_EQ(*anchored.match("dataset-1_run_old_001.bvh"),
            (std::vector<std::string>{"1", "run", "001"}));
  // Too few parts: no match. Literal text must match.
  EXPECT_FALSE(pattern.match("walk_001.bvh"));
  EXPECT_FALSE(NamePattern("take{n}").match("run_1.bvh"));
  EXPECT_EQ(*NamePattern("take{n}").match("a/take12.bvh"), std::vector<std::string>{"12"});
  // Without literal text a field is the whole name.
  EXPECT_EQ(*NamePattern("{clip_name}").match("x/64_08.bvh"), std::vector<std::string>{"64_08"});
}

TEST(NamePattern, ARegularExpressionWithNamedGroupsInEitherSpelling) {
  const NamePattern python("re:_(?P<action>[a-z]+)_(?P<style>[a-z]+)_\\d+$");
  EXPECT_EQ(python.names(), (std::vector<std::string>{"action", "style"}));
  EXPECT_EQ(*python.match("dataset-1_punch_normal_001.bvh"),
            (std::vector<std::string>{"punch", "normal"}));
  // (?<name>…), plain groups and non-capturing groups in between keep the numbering right; a
  // '(' in brackets or escaped is no group.
  const NamePattern ecma("re:^(dataset)-(?:\\d)_(?<action>[a-z(]+)_([a-z]+)_(?<take>\\d+)\\(?$");
  EXPECT_EQ(ecma.names(), (std::vector<std::string>{"action", "take"}));
  EXPECT_EQ(*ecma.match("dataset-1_bow_old_001.bvh"), (std::vector<std::string>{"bow", "001"}));
  EXPECT_FALSE(ecma.match("other-1_bow_old_001.bvh"));
}

TEST(NamePattern, BadPatternsSayWhatIsWrong) {
  auto error = [](const std::string& p) { return error_of([&] { NamePattern pattern(p); }); };
  EXPECT_NE(error("walk_take").find("no {name} field"), std::string::npos);
  EXPECT_NE(error("{action}{style}").find("cannot be told apart"), std::string::npos);
  EXPECT_NE(error("{action").find("'{' without '}'"), std::string::npos);
  EXPECT_NE(error("{a}_{a}").find("given twice"), std::string::npos);
  EXPECT_NE(error("{1x}_{y}").find("is not a label name"), std::string::npos);
  EXPECT_NE(error("{clip}_{y}").find("reserved"), std::string::npos);
  EXPECT_NE(error("re:([a-z]+)_\\d").find("no named group"), std::string::npos);
  EXPECT_NE(error("re:(?P<a>[a-z+").find("not a valid regular expression"), std::string::npos);
}

TEST(Labels, FromTheBandaiFileNames) {
  const std::vector<std::string> paths = bandai_paths();
  if (paths.size() != 12) GTEST_SKIP() << "the 12 Bandai takes are not in ../shared/data/bandai";
  const LabelTable table = labels_from_names(paths, NamePattern("{action}_{style}_{take}"));
  ASSERT_EQ(table.spans.size(), 36u);
  std::map<std::string, int> actions;
  for (const LabelSpan& s : table.spans) {
    if (s.label == 0) ++actions[s.value];
    EXPECT_EQ(s.first, 0);
    EXPECT_EQ(s.last, LabelSpan::kToEnd);
  }
  EXPECT_EQ(actions, (std::map<std::string, int>{
                         {"bow", 2}, {"dash", 1}, {"punch", 1}, {"run", 3}, {"walk", 5}}));
  // A name that does not match names the file and the pattern.
  const std::string message = error_of(
      [&] { labels_from_names(paths, NamePattern("{action}_{style}_{take}_{extra}_{more}")); });
  EXPECT_NE(message.find(paths[0] + ": error: the file name 'dataset-1_bow_normal_001'"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("'{action}_{style}_{take}_{extra}_{more}'"), std::string::npos) << message;
}

const std::vector<std::string> kPaths = {"takes/walk_1.bvh", "takes/run_1.bvh", "b/run_2.bvh"};
const std::vector<int> kFrames = {100, 80, 60};

TEST(LabelFiles, CsvOfClipsAndOfSpans) {
  const LabelTable clips = parse_label_csv(
      "# labels\nclip,action,style\nwalk_1,walk,proud\nrun_1.bvh,run,\"old, tired\"\n", kPaths,
      kFrames, "l.csv");
  EXPECT_EQ(clips.names, (std::vector<std::string>{"action", "style"}));
  ASSERT_EQ(clips.spans.size(), 4u);
  EXPECT_EQ(clips.spans[3].clip, 1);
  EXPECT_EQ(clips.spans[3].value, "old, tired");
  // b/run_2 has no label: a note says so.
  ASSERT_EQ(clips.notes.size(), 1u);
  EXPECT_NE(clips.notes[0].find("1 of 3 clips have no labels"), std::string::npos);

  const LabelTable spans = parse_label_csv(
      "clip,start,end,phase\r\nb/run_2.bvh,0,29,accelerate\r\nrun_2,30,59,steady\r\n", kPaths,
      kFrames, "s.csv");
  ASSERT_EQ(spans.spans.size(), 2u);
  EXPECT_EQ(spans.spans[1].clip, 2);
  EXPECT_EQ(spans.spans[1].first, 30);
  EXPECT_EQ(spans.spans[1].last, 59);
}

TEST(LabelFiles, EveryBadInputNamesTheFileLineAndWhatWasExpected) {
  auto error = [](const std::string& text) {
    return error_of([&] { parse_label_csv(text, kPaths, kFrames, "l.csv"); });
  };
  EXPECT_EQ(error(""),
            "l.csv:1:1: error: the file is empty: expected a header such as "
            "'clip,action,style' and rows");
  EXPECT_EQ(error("clip,action\n"),
            "l.csv:2:1: error: no labels: the file has no rows after its header");
  EXPECT_EQ(error("name,action\nwalk_1,walk\n")
                .rfind("l.csv:1:1: error: expected a header with a "
                       "'clip' column",
                       0),
            0u);
  EXPECT_EQ(error("clip,action,action\n"), "l.csv:1:13: error: duplicate column 'action'");
  EXPECT_EQ(error("clip\nwalk_1\n"),
            "l.csv:1:1: error: expected at least one label column besides clip, start and end");
  EXPECT_EQ(error("clip,action\nfly_1,fly\n")
                .rfind("l.csv:2:1: error: unknown clip 'fly_1': not one of the 3 clips mapped", 0),
            0u);
  EXPECT_EQ(error("clip,action\nwalk_1,walk,extra\n"),
            "l.csv:2:13: error: expected 2 fields as the header has, found 3");
  EXPECT_EQ(error("clip,start,end,action\nwalk_1,5,x,walk\n"),
            "l.csv:2:10: error: expected the end frame (an integer ≥ 0), found 'x'");
  EXPECT_EQ(error("clip,start,end,action\nwalk_1,-1,3,walk\n"),
            "l.csv:2:8: error: expected the start frame (an integer ≥ 0), found '-1'");
  EXPECT_EQ(error("clip,start,end,action\nwalk_1,9,3,walk\n"),
            "l.csv:2:8: error: start 9 is after end 3 (frames are inclusive: start ≤ end)");
  EXPECT_EQ(error("clip,start,end,action\nrun_1,0,80,run\n"),
            "l.csv:2:7: error: frame 80 is beyond clip 'run_1.bvh', whose frames are 0-79");
  EXPECT_EQ(error("clip,start,action\nrun_1,0,run\n"),
            "l.csv:1:1: error: expected both 'start' and 'end' columns, or neither");
  EXPECT_EQ(error("clip,action\nwalk_1,\"walk\n"),
            "l.csv:2:8: error: expected '\"' closing the quoted field");
  // Bytes that are not UTF-8: refused, and escaped in the message, which stays UTF-8.
  const std::string bad = error("clip,action\nwalk_1,w\xff\xfe\n");
  EXPECT_EQ(bad,
            "l.csv:2:8: error: expected a label value, found a label value that is not "
            "valid UTF-8");
  const std::string bad_clip = error("clip,action\nwa\xc3\x28lk,w\n");
  EXPECT_NE(bad_clip.find("unknown clip 'wa\\xC3(lk'"), std::string::npos) << bad_clip;
  EXPECT_TRUE(valid_utf8(bad_clip));
  // Two clips named alike: the path tells them apart, the stem does not.
  const std::vector<std::string> twins = {"a/run.bvh", "b/run.bvh"};
  EXPECT_EQ(error_of([&] { parse_label_csv("clip,action\nrun,run\n", twins, {}, "t.csv"); }),
            "t.csv:2:1: error: clip 'run' is ambiguous: several clips mapped have that name; "
            "give the path");
  EXPECT_NO_THROW(parse_label_csv("clip,action\nb/run.bvh,run\n", twins, {}, "t.csv"));
}

TEST(LabelFiles, JsonInBothForms) {
  const LabelTable array = parse_label_json(
      R"([{"clip": "walk_1", "action": "walk"},
          {"clip": "run_1.bvh", "start": 0, "end": 9, "action": "start", "speed": "sl\u00f6w"}])",
      kPaths, kFrames, "l.json");
  EXPECT_EQ(array.names, (std::vector<std::string>{"action", "speed"}));
  ASSERT_EQ(array.spans.size(), 3u);
  EXPECT_EQ(array.spans[2].value, "sl\xc3\xb6w");
  EXPECT_EQ(array.spans[2].last, 9);
  const LabelTable object =
      parse_label_json(R"({"walk_1": {"action": "walk"}, "b/run_2.bvh": {"action": "run"}})",
                       kPaths, kFrames, "l.json");
  ASSERT_EQ(object.spans.size(), 2u);
  EXPECT_EQ(object.spans[1].clip, 2);

  auto error = [](const std::string& text) {
    return error_of([&] { parse_label_json(text, kPaths, kFrames, "l.json"); });
  };
  EXPECT_EQ(error("[{\"clip\": \"walk_1\", \"action\": 3}]"),
            "l.json:1:31: error: expected the label 'action' as a string");
  EXPECT_EQ(error("[{\"clip\": \"walk_1\",\n \"start\": 4, \"action\": \"w\"}]"),
            "l.json:2:11: error: expected both \"start\" and \"end\", or neither");
  EXPECT_EQ(error("[{\"clip\": \"walk_1\", \"action\": \"w\""),
            "l.json:1:34: error: expected ',' or '}', found the end of the file");
  EXPECT_EQ(error("[{\"clip\": \"nope\", \"action\": \"w\"}]")
                .rfind("l.json:1:11: error: unknown clip 'nope'", 0),
            0u);
  EXPECT_EQ(error("[{\"clip\": \"walk_1\", \"clip\": \"run_1\", \"a\": \"w\"}]"),
            "l.json:1:21: error: duplicate key 'clip'");
  EXPECT_EQ(error("\"walk\""),
            "l.json:1:1: error: expected an array of objects [{\"clip\": …, \"action\": …}] or "
            "an object {\"clip name\": {\"action\": …}}");
}

TEST(Labels, PerSampleTheLaterSpanWinsAndUnlabelledFramesAreEmpty) {
  const LabelTable table =
      parse_label_csv("clip,start,end,phase\nwalk_1,0,99,walk\nwalk_1,10,19,turn\nrun_1,5,5,jump\n",
                      kPaths, kFrames, "l.csv");
  const std::vector<int> clip_of = {0, 0, 0, 1, 1, 2};
  const std::vector<int> frame_of = {0, 10, 20, 4, 5, 0};
  const Labels labels = sample_labels(table, clip_of, frame_of);
  ASSERT_EQ(labels.columns.size(), 1u);
  const LabelColumn& c = labels.columns[0];
  EXPECT_EQ(c.categories, (std::vector<std::string>{"", "jump", "turn", "walk"}));
  std::vector<std::string> values;
  for (int i = 0; i < 6; ++i) values.push_back(c.value(i));
  EXPECT_EQ(values, (std::vector<std::string>{"walk", "turn", "walk", "", "jump", ""}));
  EXPECT_EQ(c.counts(), (std::vector<int>{2, 1, 1, 2}));
  EXPECT_EQ(labels.find("phase"), &c);
  EXPECT_EQ(labels.find("action"), nullptr);
  EXPECT_NO_THROW(check_labels(labels, 6));
  EXPECT_THROW(check_labels(labels, 7), ParameterError);
  Labels broken = labels;
  broken.columns[0].codes[2] = 4;
  EXPECT_NE(error_of([&] { check_labels(broken, 6); }).find("sample 2 has value index 4"),
            std::string::npos);
}

TEST(Labels, AFilesLabelsMergeIntoTheNamesSpanBySpan) {
  // The names give every clip an action and a style; the file gives some frames of one clip
  // another action, another whole clip another style, and a new label.
  LabelTable table =
      parse_label_csv("clip,action,style\nwalk_1,walk,proud\nrun_1,run,old\nrun_2,run,tired\n",
                      kPaths, kFrames, "names");
  const LabelTable file =
      parse_label_csv("clip,start,end,action,phase\nwalk_1,10,19,turn,a\nrun_2,0,59,run,b\n",
                      kPaths, kFrames, "l.csv");
  LabelTable more = parse_label_csv("clip,style\nrun_1,calm\n", kPaths, kFrames, "more.csv");
  more.notes = {"a note"};
  merge_labels(table, file, "l.csv");
  merge_labels(table, more, "more.csv");
  EXPECT_EQ(table.names, (std::vector<std::string>{"action", "style", "phase"}));
  // The notes of both, in order.
  ASSERT_EQ(table.notes.size(), 2u);
  EXPECT_EQ(table.notes[0].rfind("l.csv: 1 of 3 clips have no labels there", 0), 0u);
  EXPECT_EQ(table.notes[1], "a note");
  const std::vector<int> clip_of = {0, 0, 0, 1, 2};
  const std::vector<int> frame_of = {0, 15, 20, 5, 5};
  const Labels labels = sample_labels(table, clip_of, frame_of);
  std::vector<std::vector<std::string>> values(3);
  for (std::size_t l = 0; l < 3; ++l) {
    for (int i = 0; i < 5; ++i) values[l].push_back(labels.columns[l].value(i));
  }
  // The file's values where it covers frames, the names' elsewhere.
  EXPECT_EQ(values[0], (std::vector<std::string>{"walk", "turn", "walk", "run", "run"}));
  EXPECT_EQ(values[1], (std::vector<std::string>{"proud", "proud", "proud", "calm", "tired"}));
  EXPECT_EQ(values[2], (std::vector<std::string>{"", "a", "", "", "b"}));
  // More than kMaxLabels names: refused, the table unchanged.
  LabelTable many;
  std::string header = "clip";
  std::string row = "walk_1";
  for (int l = 0; l < kMaxLabels - 1; ++l) {
    header += ",l" + std::to_string(l);
    row += ",v";
  }
  const LabelTable full = parse_label_csv(header + "\n" + row + "\n", kPaths, kFrames, "full");
  many = full;
  merge_labels(many, parse_label_csv("clip,l0,extra\nrun_1,w,x\n", kPaths, kFrames, "x"), "x");
  EXPECT_EQ(int(many.names.size()), kMaxLabels);
  const LabelTable before = many;
  EXPECT_EQ(error_of([&] {
              merge_labels(many, parse_label_csv("clip,w\nrun_1,w\n", kPaths, kFrames, "w"),
                           "w.csv");
            }),
            "w.csv: error: more than 32 labels together with the map's");
  EXPECT_EQ(many.names, before.names);
  EXPECT_EQ(many.spans.size(), before.spans.size());
}

TEST(Labels, ATableOfPerSampleLabelsGivesThemBack) {
  // Samples out of order, a stride, a clip in two runs of one value around another value,
  // unlabelled samples, and a clip without samples.
  const std::vector<int> clip_of = {2, 0, 0, 0, 0, 0, 2, 2, 0};
  const std::vector<int> frame_of = {4, 0, 2, 4, 6, 8, 0, 2, 10};
  LabelTable spans = parse_label_csv(
      "clip,start,end,phase\nwalk_1,0,3,a\nwalk_1,4,7,b\nwalk_1,8,99,a\nrun_2,2,4,c\n", kPaths,
      kFrames, "l.csv");
  const Labels labels = sample_labels(spans, clip_of, frame_of);
  const LabelTable table = label_table(labels, clip_of, frame_of);
  EXPECT_EQ(table.names, (std::vector<std::string>{"phase"}));
  EXPECT_EQ(table.spans.size(), 4u);  // walk_1: a, b, a; run_2: c (its frame 0 unlabelled)
  const Labels back = sample_labels(table, clip_of, frame_of);
  ASSERT_EQ(back.columns.size(), 1u);
  EXPECT_EQ(back.columns[0].categories, labels.columns[0].categories);
  EXPECT_EQ(back.columns[0].codes, labels.columns[0].codes);
  EXPECT_THROW(label_table(labels, clip_of, std::vector<int>(3)), ParameterError);
  EXPECT_THROW(label_table(labels, std::vector<int>(3), std::vector<int>(3)), ParameterError);
}

TEST(LabelVote, OtherClipsOnlyTiesToTheSmallerIndexAndToTheNearestVoter) {
  // Frames 0-1 are the query's clip (group 0) and nearest, but never vote.
  const std::vector<double> d = {0.0, 0.1, 1.0, 2.0, 2.0, 3.0, 4.0};
  const std::vector<int> codes = {0, 0, 1, 2, 1, 2, 2};
  const std::vector<int> groups = {0, 0, 1, 2, 3, 4, 5};
  EXPECT_EQ(embed::knn_label_vote(d, codes, groups, 0, 1), 1);
  // k = 2: frames 2 (code 1) and 3 (code 2; d 2.0 ties with frame 4, the smaller index wins):
  // one vote each, the nearest voter's code wins.
  EXPECT_EQ(embed::knn_label_vote(d, codes, groups, 0, 2), 1);
  // k = 3: 1, 2, 1 → code 1 by two votes.
  EXPECT_EQ(embed::knn_label_vote(d, codes, groups, 0, 3), 1);
  // k = 5: 1, 2, 1, 2, 2 → code 2.
  EXPECT_EQ(embed::knn_label_vote(d, codes, groups, 0, 5), 2);
  // Unlabelled (−1) and non-finite frames are no candidates; none left: −1.
  const std::vector<int> unlabelled = {0, 0, -1, -1, -1, -1, -1};
  EXPECT_EQ(embed::knn_label_vote(d, unlabelled, groups, 0, 3), -1);
  EXPECT_THROW(embed::knn_label_vote(d, codes, groups, 0, 0), ParameterError);
}

// The accuracy by the definition, written out plainly: for every labelled frame, its k nearest
// frames of other clips by (distance, index), the majority of their labels, ties to the label of
// the nearest among them.
double plain_accuracy(const Eigen::MatrixXd& D, const std::vector<int>& clip_of,
                      const std::vector<int>& codes, int k) {
  const int n = int(codes.size());
  int right = 0, queries = 0;
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<double, int>> others;
    for (int j = 0; j < n; ++j) {
      if (clip_of[j] != clip_of[i]) others.emplace_back(D(j, i), j);
    }
    std::sort(others.begin(), others.end());
    others.resize(std::min<std::size_t>(others.size(), std::size_t(k)));
    std::map<int, int> votes, first;
    for (std::size_t r = 0; r < others.size(); ++r) {
      const int c = codes[std::size_t(others[r].second)];
      ++votes[c];
      first.emplace(c, int(r));
    }
    int best = -1;
    for (const auto& [c, v] : votes) {
      if (best < 0 || v > votes[best] || (v == votes[best] && first[c] < first[best])) best = c;
    }
    ++queries;
    right += best == codes[std::size_t(i)];
  }
  return double(right) / queries;
}

TEST(LabelAccuracy, OnTheBandaiTakesAsTheDefinitionSays) {
  const std::vector<std::string> paths = bandai_paths();
  if (paths.size() != 12) GTEST_SKIP() << "the 12 Bandai takes are not in ../shared/data/bandai";
  std::vector<Clip> clips;
  for (const std::string& p : paths) clips.push_back(io::load_clip(p));
  ClipMapOptions options;
  options.embed.method = embed::Method::Pca;
  const ClipMap map = map_clips(clips, options);
  std::shared_ptr<features::FeatureSet> set = std::make_shared<features::FeatureSet>(*map.features);
  features::add_distances(*set);
  const Labels labels =
      sample_labels(labels_from_names(paths, NamePattern("{action}_{style}_{take}")), set->clip_of,
                    set->frame_of);
  const std::vector<LabelAccuracy> accuracy =
      label_accuracy(*set, map.embedding.coordinates, labels, 10, 5000);
  // take is "001" everywhere: one value, not measured.
  ASSERT_EQ(accuracy.size(), 2u);
  EXPECT_EQ(accuracy[0].label, "action");
  EXPECT_EQ(accuracy[1].label, "style");
  EXPECT_EQ(accuracy[0].queries, 2040);
  // The map's and the feature space's, by the plain definition.
  const Eigen::MatrixXd& Y = map.embedding.coordinates;
  Eigen::MatrixXd DY(Y.rows(), Y.rows());
  for (Eigen::Index i = 0; i < Y.rows(); ++i) {
    for (Eigen::Index j = 0; j < Y.rows(); ++j) DY(i, j) = (Y.row(i) - Y.row(j)).norm();
  }
  for (int l = 0; l < 2; ++l) {
    const std::vector<int> codes(labels.columns[std::size_t(l)].codes.begin(),
                                 labels.columns[std::size_t(l)].codes.end());
    EXPECT_DOUBLE_EQ(accuracy[std::size_t(l)].features,
                     plain_accuracy(set->D, set->clip_of, codes, 10));
    EXPECT_DOUBLE_EQ(accuracy[std::size_t(l)].map, plain_accuracy(DY, set->clip_of, codes, 10));
  }
  // Without D, from the points: the same numbers.
  features::FeatureSet points = *set;
  points.D.resize(0, 0);
  const std::vector<LabelAccuracy> from_points =
      label_accuracy(points, map.embedding.coordinates, labels, 10, 5000);
  EXPECT_DOUBLE_EQ(from_points[0].features, accuracy[0].features);
  EXPECT_DOUBLE_EQ(from_points[1].map, accuracy[1].map);
  // A map that puts each action on a point of its own keeps every action's frames together.
  Eigen::MatrixXd apart(Y.rows(), 2);
  for (Eigen::Index i = 0; i < Y.rows(); ++i) {
    apart(i, 0) = 100.0 * labels.columns[0].codes[std::size_t(i)] + 1e-3 * double(i % 7);
    apart(i, 1) = 0.0;
  }
  const std::vector<LabelAccuracy> perfect = label_accuracy(*set, apart, labels, 10, 5000);
  // dash and punch are one take each: no other clip has their label, so they cannot be right.
  int single = 0;
  for (int i = 0; i < set->num_samples(); ++i) {
    const std::string& a = labels.columns[0].value(i);
    single += a == "dash" || a == "punch";
  }
  EXPECT_DOUBLE_EQ(perfect[0].map, 1.0 - double(single) / set->num_samples());
  // A seeded sample: as many queries as asked, the same each time.
  const auto sampled = label_accuracy(*set, Y, labels, 10, 500);
  EXPECT_EQ(sampled[0].queries, 500);
  EXPECT_EQ(label_accuracy(*set, Y, labels, 10, 500)[0].map, sampled[0].map);
  EXPECT_EQ(describe_label_accuracy(accuracy).rfind("label_accuracy[action]=", 0), 0u);
  // Without the feature space: the map's figures alone.
  const auto map_only = label_accuracy(*set, Y, labels, 10, 5000, {}, false);
  EXPECT_EQ(map_only[0].map, accuracy[0].map);
  EXPECT_TRUE(std::isnan(map_only[0].features));
}

// label_accuracy() skips frames that cannot vote (a search along sorted projections with lower
// bounds of the distances); its counts of right votes are those of every frame's distance: on
// clustered points with exact ties (integer coordinates, repeated rows), unlabelled frames, a
// label some clips lack, k from 1 to 12, a map of few distinct points and a map of one column.
TEST(LabelAccuracy, TheSearchThatSkipsFramesVotesAsEveryFramesDistanceDoes) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 6; ++trial) {
    const int clips = 12 + 5 * trial;
    const int per_clip = 20 + trial * 7;
    const int n = clips * per_clip;
    const int dims = trial % 2 ? 12 : 30;
    features::FeatureSet set;
    set.distance = features::DistanceKind::PointCloud;
    set.distance_input.resize(n, dims);
    Eigen::MatrixXd map(n, trial == 5 ? 1 : 2);
    Labels labels;
    labels.columns.resize(2);
    labels.columns[0] = {"action", {"", "a", "b", "c"}, {}};
    labels.columns[1] = {"style", {"", "x", "y"}, {}};
    std::uniform_int_distribution<int> small(-3, 3), code(1, 3), coin(0, 3);
    for (int c = 0; c < clips; ++c) {
      const int action = code(random);
      for (int f = 0; f < per_clip; ++f) {
        const int i = c * per_clip + f;
        set.clip_of.push_back(c);
        set.frame_of.push_back(f);
        // Clusters by action, integer offsets (ties), some rows repeated from the frame before.
        if (f > 0 && coin(random) == 0) {
          set.distance_input.row(i) = set.distance_input.row(i - 1);
        } else {
          for (int d = 0; d < dims; ++d)
            set.distance_input(i, d) = 10.0 * action * (d % 3 == 0) + small(random);
        }
        for (Eigen::Index d = 0; d < map.cols(); ++d)
          map(i, d) = trial >= 4 ? double(small(random)) : 5.0 * action + small(random);
        labels.columns[0].codes.push_back(coin(random) == 0 ? 0 : action);
        labels.columns[1].codes.push_back(c % 4 == 0 ? 0 : 1 + (c + f / 7) % 2);
      }
    }
    for (const int k : {1, 3, 10, 12}) {
      const std::vector<LabelAccuracy> got = label_accuracy(set, map, labels, k, 0);
      ASSERT_EQ(got.size(), 2u);
      // Every frame's distance: knn_label_vote over all of them.
      for (std::size_t l = 0; l < 2; ++l) {
        std::vector<int> codes(labels.columns[l].codes.begin(), labels.columns[l].codes.end());
        for (int& c : codes) c = c == 0 ? -1 : c;
        int right_map = 0, right_features = 0, queries = 0;
        std::vector<double> dm(static_cast<std::size_t>(n)), df(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
          if (codes[std::size_t(i)] < 0) continue;
          for (int j = 0; j < n; ++j) {
            dm[std::size_t(j)] = (map.row(j) - map.row(i)).norm();
            df[std::size_t(j)] =
                euclidean_distance(set.distance_input.row(i), set.distance_input.row(j));
          }
          ++queries;
          right_map += embed::knn_label_vote(dm, codes, set.clip_of, set.clip_of[std::size_t(i)],
                                             k) == codes[std::size_t(i)];
          right_features +=
              embed::knn_label_vote(df, codes, set.clip_of, set.clip_of[std::size_t(i)], k) ==
              codes[std::size_t(i)];
        }
        EXPECT_EQ(got[l].queries, queries) << "trial " << trial << " k " << k;
        EXPECT_EQ(got[l].map, double(right_map) / queries) << "trial " << trial << " k " << k;
        EXPECT_EQ(got[l].features, double(right_features) / queries)
            << "trial " << trial << " k " << k;
      }
    }
  }
}

}  // namespace
}  // namespace motionmap::pipeline
