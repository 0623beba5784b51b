#pragma once
// How a computed map is drawn and written: the plot options the map view and the exported
// pictures share, and File → Export map (a CSV table, or a PNG, SVG or PDF picture). No widgets.
//
//   writeMap("map.svg", *maps.current(), *maps.clips());   // @throws Error
#include <vector>

#include <QString>

#include "map/map_controller.h"
#include "motionmap/render/map_plot.h"

namespace motionmap::studio {

/// The render options `map` (of `clips`) is drawn and exported with: titled with its method,
/// with a time legend, coloured by clip and the clips named when there are several, and what the
/// library wants the user to know (a bind pose left out, a joined graph) as notes under it.
render::MapPlotOptions mapPlotOptions(const MapResult& map, const std::vector<Clip>& clips);

/// Writes `map` of `clips` to `path`: .csv as pipeline::write_map_csv (clips named by file name),
/// else a picture by render::save_map_plot (.png, .svg or .pdf) with the map's parameters as a
/// note. @throws Error when the file cannot be written or its suffix is unknown.
void writeMap(const QString& path, const MapResult& map, const std::vector<Clip>& clips);

}  // namespace motionmap::studio
