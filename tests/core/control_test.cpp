// Control (core/control.h): parts and stages map their 0…1 onto the caller's range, reports never
// step backwards and are thinned to 1 % steps, the end is always reported once, and cancellation
// throws where the computation polls.
#include "motionmap/core/control.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "motionmap/core/error.h"

namespace motionmap {
namespace {

struct Recorder {
  std::vector<std::pair<double, std::string>> reports;
  bool stop = false;
  Control control() {
    return Control([this](double f, std::string_view s) { reports.emplace_back(f, s); },
                   [this] { return stop; });
  }
};

TEST(Control, DefaultReportsNothingAndNeverCancels) {
  const Control none;
  EXPECT_FALSE(none.reports());
  EXPECT_FALSE(none.cancelled());
  EXPECT_NO_THROW(none.update(0.5));
  EXPECT_NO_THROW(none.stage("eigen", 0.2, 0.4).update(1.0));
  EXPECT_NO_THROW(none.finish());
  EXPECT_NO_THROW(none.check());
}

TEST(Control, PartsAndStagesMapTheirFractionsOntoTheWhole) {
  Recorder r;
  const Control whole = r.control();
  const Control stage = whole.stage("neighbours", 0.2, 0.6);  // reports its start, 0.2
  stage.update(0.5);                                          // 0.2 + 0.5·0.4
  const Control inner = stage.part(0.5, 1.0);                 // [0.4, 0.6] of the whole
  inner.update(0.5);
  inner.finish();
  ASSERT_EQ(r.reports.size(), 4u);
  EXPECT_DOUBLE_EQ(r.reports[0].first, 0.2);
  EXPECT_EQ(r.reports[0].second, "neighbours");
  EXPECT_DOUBLE_EQ(r.reports[1].first, 0.4);
  EXPECT_DOUBLE_EQ(r.reports[2].first, 0.5);
  EXPECT_EQ(r.reports[2].second, "neighbours");  // a part keeps its stage's name
  EXPECT_DOUBLE_EQ(r.reports[3].first, 0.6);
  EXPECT_EQ(inner.stage_name(), "neighbours");
}

TEST(Control, ReportsNeverStepBackwardsAndAreThinnedToOnePercent) {
  Recorder r;
  const Control whole = r.control();
  whole.update(0.5);
  whole.part(0.0, 0.4).update(1.0);  // 0.4 < 0.5: not reported, nothing goes back
  whole.update(0.505);               // within 1 % of 0.5: skipped
  whole.update(0.52);
  whole.update(-3.0);  // clamped to 0, which is behind: skipped
  whole.update(7.0);   // clamped to 1
  whole.finish();      // 1 again: not repeated
  ASSERT_EQ(r.reports.size(), 3u);
  EXPECT_DOUBLE_EQ(r.reports[0].first, 0.5);
  EXPECT_DOUBLE_EQ(r.reports[1].first, 0.52);
  EXPECT_DOUBLE_EQ(r.reports[2].first, 1.0);
}

TEST(Control, FinishIsReportedEvenWithinOnePercent) {
  Recorder r;
  const Control part = r.control().part(0.0, 0.5);
  part.update(0.99);  // 0.495
  part.finish();      // 0.5: forced
  ASSERT_EQ(r.reports.size(), 2u);
  EXPECT_DOUBLE_EQ(r.reports[1].first, 0.5);
}

TEST(Control, CopiesShareWhatWasReported) {
  Recorder r;
  const Control a = r.control();
  const Control b = a;  // NOLINT(performance-unnecessary-copy-initialization): the point here
  a.update(0.7);
  b.update(0.6);  // behind what a reported
  ASSERT_EQ(r.reports.size(), 1u);
}

TEST(Control, CancellationThrowsWhereTheComputationPolls) {
  Recorder r;
  const Control whole = r.control();
  EXPECT_NO_THROW(whole.update(0.1));
  r.stop = true;
  EXPECT_TRUE(whole.cancelled());
  EXPECT_THROW(whole.check(), Cancelled);
  EXPECT_THROW(whole.update(0.3), Cancelled);
  const std::size_t before = r.reports.size();
  EXPECT_THROW(whole.stage("eigen", 0.5, 1.0), Cancelled);
  // The stage's start was reported before the poll threw.
  ASSERT_EQ(r.reports.size(), before + 1);
  EXPECT_EQ(r.reports.back().second, "eigen");
  EXPECT_NO_THROW(whole.finish());  // finishing never polls
}

TEST(Control, OutOfOrderRangesAreClamped) {
  Recorder r;
  const Control part = r.control().part(0.8, 0.3);  // end before begin: an empty range at 0.8
  part.update(0.5);
  part.finish();
  ASSERT_FALSE(r.reports.empty());
  for (const auto& [fraction, stage] : r.reports) EXPECT_DOUBLE_EQ(fraction, 0.8);
  const Control clamped = Control().part(-1.0, 2.0);  // the whole range
  EXPECT_NO_THROW(clamped.update(0.5));
}

}  // namespace
}  // namespace motionmap
