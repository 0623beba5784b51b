// Compiled as part of the embed stage (tests/CMakeLists.txt: layering_wrong_include), which links
// only core: the include below must fail with "No such file or directory", because embed/ is
// numerics on matrices and knows nothing of files. The ctest layering_wrong_include_fails checks
// that it does.
#include "motionmap/io/load.h"

int layering_wrong_include() {
  return 0;
}
