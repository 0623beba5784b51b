#include "explore/map_coloring.h"

#include <algorithm>
#include <exception>
#include <string>

#include <QFileInfo>

#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/render/map_plot.h"

namespace motionmap::studio {

QColor MapColoring::Entry::color() const {
  return render::category_color(category);
}

MapColoring::MapColoring(MapView* view, std::function<const MapSource*()> source,
                         std::function<std::vector<int>()> clipFrames, QObject* parent)
    : QObject(parent),
      m_view(view),
      m_source(std::move(source)),
      m_clipFrames(std::move(clipFrames)) {
  connect(view, &MapView::mapReplaced, this, &MapColoring::mapReplaced);
}

const pipeline::LabelColumn* MapColoring::column(const std::string& name) const {
  // With a label file: the map's labels and the file's, merged (every label there).
  if (!m_fileLabels.empty()) return m_fileLabels.find(name);
  if (m_savedLabels) return m_savedLabels->find(name);
  return m_nameLabels.find(name);
}

QStringList MapColoring::choices() const {
  QStringList out{timeChoice()};
  const MapSource* source = m_source();
  if (source && source->clipCount() > 1) out << clipChoice();
  for (const pipeline::Labels* l : {m_savedLabels ? m_savedLabels.get() : &m_nameLabels,
                                    static_cast<const pipeline::Labels*>(&m_fileLabels)}) {
    for (const pipeline::LabelColumn& c : l->columns) {
      const QString name = QString::fromStdString(c.name);
      if (!out.contains(name)) out << name;
    }
  }
  return out;
}

bool MapColoring::setColorBy(const QString& name) {
  if (!choices().contains(name)) {
    emit failed(
        tr("The map has no label '%1' to colour by (it has: %2)").arg(name, choices().join(", ")));
    return false;
  }
  m_colorBy = name;
  build();
  apply();
  return true;
}

bool MapColoring::build() {
  m_codes.clear();
  m_entries.clear();
  if (m_colorBy == timeChoice()) return true;
  const MapSource* source = m_source();
  const MapSource::Samples samples = source ? source->samples() : MapSource::Samples{};
  if (!samples.points || !samples.clipOf) return false;
  const std::size_t n = std::size_t(samples.points->rows());
  std::vector<QString> values;
  if (m_colorBy == clipChoice()) {
    // The clips' file names, in clip order (as `--color-by clip`).
    for (const QString& path : source->clipPaths()) values.push_back(QFileInfo(path).fileName());
    m_codes.assign(samples.clipOf->begin(), samples.clipOf->end());
  } else {
    const pipeline::LabelColumn* c = column(m_colorBy.toStdString());
    if (!c || c->codes.size() != n) return false;
    for (const std::string& value : c->categories)
      values.push_back(value.empty() ? tr("(none)") : QString::fromStdString(value));
    m_codes.assign(c->codes.begin(), c->codes.end());
  }
  if (m_codes.size() != n) {
    m_codes.clear();
    return false;
  }
  std::vector<int> counts(values.size(), 0);
  for (const int code : m_codes) {
    if (code >= 0 && std::size_t(code) < counts.size()) ++counts[std::size_t(code)];
  }
  // The CLI's rule (render::category_slots): the most frequent values coloured, the rest grey.
  const std::vector<int> slot_of = render::category_slots(counts);
  m_entries.resize(values.size());
  for (std::size_t v = 0; v < values.size(); ++v)
    m_entries[v] = {values[v], counts[v], slot_of[v], true};
  return true;
}

void MapColoring::apply() {
  if (m_entries.empty()) {
    m_view->setSampleCategories({});
  } else {
    std::vector<int> categories(m_codes.size());
    for (std::size_t i = 0; i < m_codes.size(); ++i) {
      const int code = m_codes[i];
      const Entry* e = code >= 0 && std::size_t(code) < m_entries.size()
                           ? &m_entries[std::size_t(code)]
                           : nullptr;
      categories[i] = !e ? -1 : e->shown ? e->category : MapView::kHiddenCategory;
    }
    m_view->setSampleCategories(std::move(categories));
  }
  emit changed();
}

void MapColoring::setShown(int entry, bool shown) {
  if (entry < 0 || entry >= int(m_entries.size()) || m_entries[std::size_t(entry)].shown == shown)
    return;
  m_entries[std::size_t(entry)].shown = shown;
  apply();
}

void MapColoring::solo(int entry) {
  if (entry < 0 || entry >= int(m_entries.size())) return;
  bool alone = m_entries[std::size_t(entry)].shown;
  for (std::size_t e = 0; e < m_entries.size(); ++e) {
    if (int(e) != entry && m_entries[e].shown) alone = false;
  }
  for (std::size_t e = 0; e < m_entries.size(); ++e) m_entries[e].shown = alone || int(e) == entry;
  apply();
}

void MapColoring::showAll() {
  for (Entry& e : m_entries) e.shown = true;
  apply();
}

int MapColoring::shownSamples() const {
  int n = 0;
  for (const Entry& e : m_entries) n += e.shown ? e.count : 0;
  return n;
}

bool MapColoring::labelsFromNames(const QString& pattern) {
  const MapSource* source = m_source();
  const MapSource::Samples samples = source ? source->samples() : MapSource::Samples{};
  if (m_savedLabels) {
    emit failed(tr("A saved map has its own labels (View → Colour by)"));
    return false;
  }
  if (!samples.clipOf || !samples.frameOf) {
    emit failed(tr("Labels from file names need a map: open clips first"));
    return false;
  }
  const QStringList paths = source->clipPaths();
  try {
    std::vector<std::string> names;
    for (const QString& path : paths) names.push_back(path.toStdString());
    const pipeline::NamePattern parsed(pattern.toStdString());
    pipeline::LabelTable table = pipeline::labels_from_names(names, parsed);
    pipeline::Labels labels = pipeline::sample_labels(table, *samples.clipOf, *samples.frameOf);
    // A label file read before is merged into the new names' labels (as the CLI merges them).
    pipeline::Labels merged;
    if (!m_filePath.isEmpty()) {
      merged =
          withFile(table, m_fileTable, m_filePath.toStdString(), *samples.clipOf, *samples.frameOf);
    }
    m_nameTable = std::move(table);
    m_nameLabels = std::move(labels);
    m_fileLabels = std::move(merged);
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
  m_pattern = pattern;
  m_patternPaths = paths;
  // The first label the pattern names colours the map.
  return setColorBy(QString::fromStdString(m_nameLabels.columns.front().name));
}

bool MapColoring::labelsFromFile(const QString& path) {
  const MapSource* source = m_source();
  const MapSource::Samples samples = source ? source->samples() : MapSource::Samples{};
  if (!samples.clipOf || !samples.frameOf) {
    emit failed(tr("Labels from a file need a map: open clips or a map first"));
    return false;
  }
  const QStringList paths = source->clipPaths();
  pipeline::LabelTable table;
  pipeline::Labels labels;
  try {
    std::vector<std::string> names;
    for (const QString& p : paths) names.push_back(p.toStdString());
    std::vector<int> frames = m_clipFrames ? m_clipFrames() : std::vector<int>{};
    if (frames.size() != names.size()) frames.clear();
    table = pipeline::read_label_file(path.toStdString(), names, frames);
    labels = withFile(baseTable(*samples.clipOf, *samples.frameOf), table, path.toStdString(),
                      *samples.clipOf, *samples.frameOf);
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
  m_fileTable = std::move(table);
  m_fileLabels = std::move(labels);
  m_filePath = path;
  m_filePaths = paths;
  // The first label the file names colours the map.
  return setColorBy(QString::fromStdString(m_fileTable.names.front()));
}

pipeline::LabelTable MapColoring::baseTable(std::span<const int> clipOf,
                                            std::span<const int> frameOf) const {
  if (m_savedLabels) return pipeline::label_table(*m_savedLabels, clipOf, frameOf);
  return m_nameTable;
}

pipeline::Labels MapColoring::withFile(pipeline::LabelTable base, const pipeline::LabelTable& file,
                                       const std::string& path, std::span<const int> clipOf,
                                       std::span<const int> frameOf) {
  // One rule with the CLI's (`map --labels-from-name … --labels FILE`): pipeline::merge_labels.
  pipeline::merge_labels(base, file, path);
  return pipeline::sample_labels(base, clipOf, frameOf);
}

void MapColoring::mergeFileLabels() {
  m_fileLabels = {};
  const MapSource* source = m_source();
  if (m_filePath.isEmpty() || !source || source->clipPaths() != m_filePaths) {
    m_fileTable = {};
    m_filePath.clear();
    m_filePaths.clear();
    return;
  }
  const MapSource::Samples samples = source->samples();
  if (!samples.clipOf || !samples.frameOf) return;
  try {
    m_fileLabels = withFile(baseTable(*samples.clipOf, *samples.frameOf), m_fileTable,
                            m_filePath.toStdString(), *samples.clipOf, *samples.frameOf);
  } catch (const std::exception&) {
    m_fileLabels = {};
  }
}

void MapColoring::mapReplaced() {
  const MapSource* source = m_source();
  const auto* saved = dynamic_cast<const SavedMapSource*>(source);
  m_savedLabels = saved && saved->map() ? std::shared_ptr<const pipeline::Labels>(
                                              saved->map(), &saved->map()->file().labels)
                                        : nullptr;
  if (m_savedLabels && m_savedLabels->empty()) m_savedLabels.reset();
  // Labels from names stay with the clips they were read from (a map of other clips drops them).
  if (saved || !source || source->clipPaths() != m_patternPaths) {
    m_nameTable = {};
    m_nameLabels = {};
    m_pattern.clear();
    m_patternPaths.clear();
  } else if (!m_pattern.isEmpty()) {
    const MapSource::Samples samples = source->samples();
    if (samples.clipOf && samples.frameOf) {
      try {
        std::vector<std::string> names;
        for (const QString& path : m_patternPaths) names.push_back(path.toStdString());
        m_nameTable =
            pipeline::labels_from_names(names, pipeline::NamePattern(m_pattern.toStdString()));
        m_nameLabels = pipeline::sample_labels(m_nameTable, *samples.clipOf, *samples.frameOf);
      } catch (const std::exception&) {
        m_nameTable = {};
        m_nameLabels = {};
      }
    }
  }
  // A label file's labels stay with the clips they were read against, saved map or not, merged
  // into the new map's labels.
  mergeFileLabels();
  // The same colouring on the new map when it has it (the values shown kept by name).
  std::vector<QString> hidden;
  for (const Entry& e : m_entries) {
    if (!e.shown) hidden.push_back(e.value);
  }
  if (!choices().contains(m_colorBy)) m_colorBy = timeChoice();
  if (!m_view->hasMap() || !build()) {
    m_codes.clear();
    m_entries.clear();
  }
  for (Entry& e : m_entries)
    e.shown = std::find(hidden.begin(), hidden.end(), e.value) == hidden.end();
  apply();
}

}  // namespace motionmap::studio
