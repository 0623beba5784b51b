#pragma once
// Acclaim ASF/AMC, CMU's native format, in one include: asf.h reads the skeleton, amc.h the
// motion (and both files into a Clip with load_asf_amc()). Prefer the one you need.
#include "motionmap/io/amc.h"
#include "motionmap/io/asf.h"
