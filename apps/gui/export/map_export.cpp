#include "export/map_export.h"

#include <fstream>

#include <QFileInfo>

#include "motionmap/core/error.h"
#include "motionmap/pipeline/map_csv.h"

namespace motionmap::studio {

namespace {
QString fileName(const Clip& clip) {
  return QFileInfo(QString::fromStdString(clip.path)).fileName();
}
}  // namespace

render::MapPlotOptions mapPlotOptions(const MapResult& map, const std::vector<Clip>& clips) {
  render::MapPlotOptions options;
  options.title = methodLabel(map.map.embedding.method);
  options.time_legend = true;
  if (clips.size() > 1) {  // several clips: colour by clip, named in the legend
    for (const Clip& clip : clips) options.clip_names << fileName(clip);
  }
  for (const auto& note : map.map.features->notes) options.notes << QString::fromStdString(note);
  for (const auto& note : map.map.embedding.notes) options.notes << QString::fromStdString(note);
  for (const auto& warning : map.map.embedding.warnings)
    options.notes << QString::fromStdString(warning);
  return options;
}

void writeMap(const QString& path, const MapResult& map, const std::vector<Clip>& clips) {
  if (QFileInfo(path).suffix().compare("csv", Qt::CaseInsensitive) == 0) {
    std::ofstream out(path.toStdString());
    if (!out) throw Error("cannot write " + path.toStdString());
    std::vector<std::string> files;
    for (const Clip& clip : clips) files.push_back(fileName(clip).toStdString());
    pipeline::write_map_csv(out, map.map, map.options, files);
    if (!out.flush()) throw Error("cannot write " + path.toStdString());
  } else {
    render::MapPlotOptions options = mapPlotOptions(map, clips);
    options.notes << QString::fromStdString(map.parameters);
    render::save_map_plot(path.toStdString(), map.map.embedding.coordinates,
                          map.map.features->segment_starts, options);
  }
}

}  // namespace motionmap::studio
