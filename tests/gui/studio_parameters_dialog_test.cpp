// Motion → Parameters… says which k the library accepts and why (motionmap/embed/k_range.h),
// instead of refusing 0 silently and stopping at 1 000 without a word.
#include <gtest/gtest.h>

#include <QLabel>
#include <QPushButton>
#include <QSpinBox>
#include <QTest>

#include "app/parameter_dialogs.h"
#include "motionmap/embed/k_range.h"

namespace motionmap::studio::testing {

TEST(StudioParametersDialog, SaysTheRangeOfKAndWhy) {
  constexpr int frames = 240;
  MapParameters now;
  now.k = 20;
  MapParametersDialog dialog(now, frames);
  QSpinBox* k = dialog.kField();
  const QString lo = QString::number(embed::kMinNeighbors);
  const QString hi = QString::number(embed::max_neighbors(frames));
  EXPECT_TRUE(dialog.okButton()->isEnabled());
  EXPECT_TRUE(dialog.kHint()->text().contains(lo)) << dialog.kHint()->text().toStdString();
  EXPECT_TRUE(dialog.kHint()->text().contains(hi)) << dialog.kHint()->text().toStdString();
  EXPECT_TRUE(dialog.kHint()->text().contains(QString::number(frames)));

  // 0 is typed, and refused with a word.
  k->setValue(0);
  EXPECT_EQ(k->value(), 0);
  EXPECT_FALSE(dialog.okButton()->isEnabled());
  EXPECT_TRUE(dialog.kHint()->text().contains("k = 0 is out of range"))
      << dialog.kHint()->text().toStdString();
  EXPECT_TRUE(dialog.kHint()->text().contains(hi));

  // Values above 1 000 can be typed (the field no longer stops there).
  k->selectAll();
  QTest::keyClicks(k, "100000");
  EXPECT_EQ(k->value(), 100000);
  EXPECT_FALSE(dialog.okButton()->isEnabled());
  EXPECT_TRUE(dialog.kHint()->text().contains("k = 100000 is out of range"));

  // The library's bounds are the dialog's.
  k->setValue(embed::max_neighbors(frames));
  EXPECT_TRUE(dialog.okButton()->isEnabled());
  k->setValue(embed::max_neighbors(frames) + 1);
  EXPECT_FALSE(dialog.okButton()->isEnabled());
  k->setValue(embed::kMinNeighbors);
  EXPECT_TRUE(dialog.okButton()->isEnabled());
  QString error;
  const auto p = dialog.parameters(error);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->k, embed::kMinNeighbors);

  // Without a map the frame count is unknown: large values wait for the library's check.
  MapParametersDialog unknown(now, 0);
  unknown.kField()->setValue(100000);
  EXPECT_TRUE(unknown.okButton()->isEnabled());
  unknown.kField()->setValue(0);
  EXPECT_FALSE(unknown.okButton()->isEnabled());
  EXPECT_TRUE(unknown.kHint()->text().contains("out of range"));
}

}  // namespace motionmap::studio::testing
