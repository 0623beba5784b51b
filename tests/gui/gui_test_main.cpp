// GoogleTest main for the app's tests: one QApplication (offscreen under ctest) for all of them,
// settings isolated from the user's and from the other test processes that ctest runs at the same
// time (each process keeps its QSettings in a temporary folder of its own), and from the tests
// before (cleared as each test starts: a window restores the last map and synthesis parameters).
#include <gtest/gtest.h>

#include <QApplication>
#include <QSettings>
#include <QStandardPaths>
#include <QTemporaryDir>

namespace {
struct ClearSettings : ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo&) override { QSettings().clear(); }
};
}  // namespace

int main(int argc, char** argv) {
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  qputenv("MOTIONMAP_STUDIO_NO_CONFIRM", "1");
  QStandardPaths::setTestModeEnabled(true);
  QApplication app(argc, argv);
  QApplication::setOrganizationName("MotionMapTests");
  QApplication::setApplicationName("MotionMap Studio Tests");
  const QTemporaryDir settings_dir;
  if (!settings_dir.isValid()) return 2;
  QSettings::setDefaultFormat(QSettings::IniFormat);
  QSettings::setPath(QSettings::IniFormat, QSettings::UserScope, settings_dir.path());
  ::testing::InitGoogleTest(&argc, argv);
  ::testing::UnitTest::GetInstance()->listeners().Append(new ClearSettings);
  return RUN_ALL_TESTS();
}
