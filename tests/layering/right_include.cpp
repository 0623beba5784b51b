// The counterpart of wrong_include.cpp: the same target set-up with headers of the stage itself
// and of the stages it links compiles (built with the tests, so a broken set-up shows at once).
#include "motionmap/core/error.h"
#include "motionmap/embed/embed.h"

int layering_right_include() {
  return 0;
}
