#pragma once
// Shared set-up of the offscreen Studio tests: the sample swing and a shown window with its map.
#include <gtest/gtest.h>

#include <QTest>
#include <memory>

#include "main_window.h"
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
