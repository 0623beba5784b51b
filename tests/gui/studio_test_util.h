#pragma once
// Shared set-up of the offscreen Studio tests: the sample swing, a shown window with its map, and
// paths along a map's trajectory.
#include <gtest/gtest.h>

#include <QTest>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

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

/// Shows `w` (non-interactive, 1280 × 720) with the clips `paths` (one skeleton: the first opened,
/// the others added) on one PCA map; false (the failure recorded) when one does not open or the
/// map does not come.
inline bool showOnPcaMap(MainWindow& w, const std::vector<std::string>& paths) {
  w.setInteractive(false);
  w.resize(1280, 720);
  w.show();
  w.setMethod(embed::Method::Pca);
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const QString path = QString::fromStdString(paths[i]);
    if (!(i == 0 ? w.openFile(path) : w.addFile(path))) {
      ADD_FAILURE() << paths[i] << ": " << w.lastError().toStdString();
      return false;
    }
  }
  const bool shown = QTest::qWaitFor(
      [&] {
        return w.currentMap() != nullptr && !w.isComputing() &&
               w.clipCount() == static_cast<int>(paths.size());
      },
      kTimeoutMs);
  EXPECT_TRUE(shown) << w.lastError().toStdString();
  return shown;
}

}  // namespace motionmap::studio::testing
