#pragma once
// The 2-D nearest-neighbour index of a saved map's points under its mapfile name: it is
// synth::PointIndex (synth/point_index.h), the one k-d tree of map points, which the blender and
// the routes search too.
#include "motionmap/synth/point_index.h"

namespace motionmap::mapfile {

using Neighbor = synth::Neighbor;
using PointIndex = synth::PointIndex;

}  // namespace motionmap::mapfile
