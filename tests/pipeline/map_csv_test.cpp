#include "motionmap/pipeline/map_csv.h"

#include <sstream>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/sample/sample_clip.h"
#include "support/error_message.h"

namespace motionmap::pipeline {
using embed::Method;
namespace {

std::string parse_message(const std::string& text) {
  return test::error_message<ParseError>([&] { parse_map_csv(text, "m.csv"); });
}

ClipMap sample_map(std::span<const Clip> clips, const ClipMapOptions& options) {
  return map_clips(clips, options);
}

TEST(MapCsv, WrittenMapReadsBackExactly) {
  std::vector<Clip> clips{sample::make_sample_clip(sample::SampleKind::Swing),
                          sample::make_sample_clip(sample::SampleKind::Walk)};
  for (const auto& cs : {std::vector<Clip>{clips[0]}, clips}) {
    for (int dims : {2, 3}) {
      ClipMapOptions options;
      options.embed.method = Method::Pca;
      options.embed.dimensions = dims;
      options.features.stride = 3;
      const ClipMap map = sample_map(cs, options);
      std::ostringstream out;
      const std::vector<std::string> files{"dir/a.bvh", "b.bvh"};
      write_map_csv(out, map, options, std::span(files).first(cs.size()));
      const std::string text = out.str();
      EXPECT_EQ(text.rfind("# motionmap map method=pca dims=" + std::to_string(dims), 0), 0u)
          << text.substr(0, 80);
      EXPECT_NE(text.find(cs.size() > 1 ? "files=a.bvh,b.bvh\n" : "files=a.bvh\n"),
                std::string::npos);

      const MapTable table = parse_map_csv(text, "m.csv");
      ASSERT_EQ(table.num_rows(), map.features->num_samples());
      EXPECT_EQ(table.coords, map.embedding.coordinates);  // 17 digits: bit-exact
      EXPECT_EQ(table.frame_of, map.features->frame_of);
      EXPECT_EQ(table.clip_of, map.features->clip_of);
      EXPECT_NO_THROW(table.check_matches(*map.features));
      EXPECT_NO_THROW(table.check_matches(features::select_samples(cs, options.features)));
    }
  }
}

TEST(MapCsv, LabelColumnsFollowTheCoordinatesAndReadBack) {
  const std::vector<Clip> clips{sample::make_sample_clip(sample::SampleKind::Swing),
                                sample::make_sample_clip(sample::SampleKind::Walk)};
  ClipMapOptions options;
  options.embed.method = Method::Pca;
  options.features.stride = 5;
  const ClipMap map = sample_map(clips, options);
  const std::vector<std::string> files{"swing.bvh", "walk.bvh"};
  const LabelTable table = parse_label_csv(
      "clip,start,end,kind\nswing,0,1000,\"swing, golf\"\nwalk,0,1000,walk\nwalk,0,20,\n", files,
      {}, "l.csv");
  const Labels labels = sample_labels(table, map.features->clip_of, map.features->frame_of);
  const std::vector<LabelAccuracy> accuracy = {{"kind", 0.5, 0.75, 12, 10}};
  std::ostringstream out;
  write_map_csv(out, map, options, files, &labels, accuracy);
  const std::string text = out.str();
  EXPECT_NE(text.find("\n# label accuracy (map/features, 10-NN vote among other clips' frames) "
                      "label_accuracy[kind]=0.5000/0.7500\n"),
            std::string::npos)
      << text.substr(0, 400);
  EXPECT_NE(text.find("\nclip,frame,x,y,kind\n"), std::string::npos);
  EXPECT_NE(text.find(",\"swing, golf\"\n"), std::string::npos);
  const MapTable back = parse_map_csv(text, "m.csv");
  EXPECT_EQ(back.coords, map.embedding.coordinates);
  ASSERT_EQ(back.labels.columns.size(), 1u);
  EXPECT_EQ(back.labels.columns[0].name, "kind");
  EXPECT_EQ(back.labels.columns[0].categories, labels.columns[0].categories);
  EXPECT_EQ(back.labels.columns[0].codes, labels.columns[0].codes);
  // A label column named like a map column, or given twice, is refused.
  EXPECT_EQ(parse_message("frame,x,y,kind,kind\n0,1,2,a,b\n"),
            "m.csv:1:16: error: duplicate column 'kind'");
  EXPECT_EQ(parse_message("frame,x,y,kind,time\n0,1,2,a,b\n"),
            "m.csv:1:11: error: expected label columns after the map's: labels: the label name "
            "'time', which is reserved (clip, frame, x, y, z, time, start and end are not labels)");
  EXPECT_EQ(parse_message("frame,x,y,kind\n0,1,2,a,b\n"),
            "m.csv:2:9: error: expected 4 fields as in the header, found 5");
}

TEST(MapCsv, SelectSamplesIsBuildFeaturesWithoutMatrices) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Swing);
  features::FeatureOptions options;
  options.first_frame = 10;
  options.end_frame = 200;
  options.stride = 4;
  const auto full = features::build_features(std::span(&clip, 1), options);
  const auto selected = features::select_samples(std::span(&clip, 1), options);
  EXPECT_EQ(selected.frame_of, full.frame_of);
  EXPECT_EQ(selected.clip_of, full.clip_of);
  EXPECT_EQ(selected.segment_starts, full.segment_starts);
  EXPECT_EQ(selected.joints, full.joints);
  EXPECT_EQ(selected.X.size(), 0);
  EXPECT_EQ(selected.D.size(), 0);
}

TEST(MapCsv, CheckMatchesNamesTheFirstDifferentRow) {
  const MapTable table = parse_map_csv("# c\nframe,x,y\n1,0,0\n2,1,0\r\n\n4,2,0\n", "m.csv");
  EXPECT_EQ(table.lines, (std::vector<std::size_t>{3, 4, 6}));
  features::FeatureSet set;
  set.clip_of = {0, 0, 0};
  set.frame_of = {1, 2, 3};
  try {
    table.check_matches(set);
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_STREQ(
        e.what(),
        "m.csv:6: row 3 is clip 0 frame 4, but the clips' sample 3 is clip 0 frame 3: not a "
        "map of these clips with these options");
  }
  set.frame_of = {1, 2};
  set.clip_of = {0, 0};
  try {
    table.check_matches(set);
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("m.csv: 3 map rows, but the clips give 2 samples"),
              std::string::npos)
        << e.what();
  }
}

TEST(MapCsv, BadFilesNameLineAndColumn) {
  EXPECT_EQ(
      parse_message(""),
      "m.csv:1:1: error: expected the header of a map (frame,x,y or clip,frame,x,y), found none");
  EXPECT_EQ(
      parse_message("# only\n"),
      "m.csv:2:1: error: expected the header of a map (frame,x,y or clip,frame,x,y), found none");
  EXPECT_EQ(parse_message("t,x,y\n0,1,2\n"),
            "m.csv:1:1: error: expected the header of a map (frame,x,y or clip,frame,x,y, with ,z "
            "in 3-D), found 't,x,y'");
  EXPECT_EQ(parse_message("frame,x,y\n"),
            "m.csv:2:1: error: expected map rows after the header, found none");
  EXPECT_EQ(parse_message("frame,x,y\n1,2\n"),
            "m.csv:2:4: error: expected 3 fields as in the header, found 2");
  EXPECT_EQ(parse_message("frame,x,y\n1,2,3,4\n"),
            "m.csv:2:7: error: expected 3 fields as in the header, found 4");
  EXPECT_EQ(parse_message("frame,x,y\n-1,2,3\n"),
            "m.csv:2:1: error: expected a frame number (an integer ≥ 0), found '-1'");
  EXPECT_EQ(parse_message("clip,frame,x,y\n0.5,1,2,3\n"),
            "m.csv:2:1: error: expected a clip number (an integer ≥ 0), found '0.5'");
  EXPECT_EQ(parse_message("frame,x,y\n1, nan ,3\n"),
            "m.csv:2:4: error: expected a finite coordinate, found 'nan'");
  EXPECT_EQ(parse_message("frame,x,y\n1,,3\n"),
            "m.csv:2:3: error: expected a finite coordinate, found ''");
  EXPECT_EQ(parse_message("Frame,X,Y,Z\n1,2,3,4\n"), "no error");
}

}  // namespace
}  // namespace motionmap::pipeline
