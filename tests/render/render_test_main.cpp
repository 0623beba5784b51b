// GoogleTest main for the render tests. The render library draws only under an application its
// caller made, so this main makes one QGuiApplication for all the tests (offscreen unless
// QT_QPA_PLATFORM names a platform), as the CLI and Studio do.
//
// With MOTIONMAP_RENDER_TESTS_NO_APP set it makes none: the death tests that check what drawing
// without an application reports set it and re-run this program for one test in a child process.
#include <gtest/gtest.h>

#include <QGuiApplication>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (qEnvironmentVariableIsSet("MOTIONMAP_RENDER_TESTS_NO_APP")) return RUN_ALL_TESTS();
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  QGuiApplication app(argc, argv);
  return RUN_ALL_TESTS();
}
