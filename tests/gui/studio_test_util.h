#pragma once
// Shared set-up of the offscreen Studio tests: the sample swing, a shown window with its map, and
// paths along a map's trajectory.
#include <gtest/gtest.h>

#include <QTest>
#include <cstdlib>
#include <memory>

#include "app/main_window.h"
#include "motionmap/sample/sample_clip.h"

namespace motionmap::studio::testing {

/// How long a test waits for a map or a synthesis (generous: CI machines are slow and shared).
constexpr int kTimeoutMs = 120000;

/// The built-in swing, `seconds` long.
inline Clip swing(double seconds = 2.0) {
  sample::SampleOptions options;
  options.seconds = seconds;
  return sample::make_sample_clip(sample::SampleKind::Swing, options);
}

/// A timed path along the trajectory of `map` from row `from` to row `to`, `seconds` long.
inline synth::MapPath pathAlong(const MapResult& map, int from, int to, double seconds) {
  synth::MapPath path;
  const int steps = std::abs(to - from);
  for (int i = 0; i <= steps; ++i) {
    path.points.push_back(map.blender->sample_point(from + (to > from ? i : -i)));
    path.times.push_back(seconds * i / steps);
  }
  return path;
}

/// A shown, non-interactive window with the sample's map computed for `method`.
inline std::unique_ptr<MainWindow> windowWithMap(embed::Method method = embed::Method::Isomap) {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(1000, 600);
  w->show();
  w->setMethod(method);
  w->openClip(swing());
  EXPECT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); }, kTimeoutMs));
  EXPECT_NE(w->currentMap(), nullptr) << w->lastError().toStdString();
  return w;
}

}  // namespace motionmap::studio::testing
