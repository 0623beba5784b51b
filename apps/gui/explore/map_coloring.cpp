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

MapColoring::MapColoring(MapView* view, std::function<const MapSource*()> source, QObject* parent)
    : QObject(parent), m_view(view), m_source(std::move(source)) {
  connect(view, &MapView::mapReplaced, this, &MapColoring::mapReplaced);
}

const pipeline::Labels* MapColoring::labels() const {
  if (m_savedLabels) return m_savedLabels.get();
  return m_nameLabels.empty() ? nullptr : &m_nameLabels;
}

QStringList MapColoring::choices() const {
  QStringList out{timeChoice()};
  const MapSource* source = m_source();
  if (source && source->clipCount() > 1) out << clipChoice();
  if (const pipeline::Labels* l = labels()) {
    for (const pipeline::LabelColumn& column : l->columns)
      out << QString::fromStdString(column.name);
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
    const pipeline::Labels* l = labels();
    const pipeline::LabelColumn* column = l ? l->find(m_colorBy.toStdString()) : nullptr;
    if (!column || column->codes.size() != n) return false;
    for (const std::string& value : column->categories)
      values.push_back(value.empty() ? tr("(none)") : QString::fromStdString(value));
    m_codes.assign(column->codes.begin(), column->codes.end());
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
    m_nameLabels = pipeline::sample_labels(pipeline::labels_from_names(names, parsed),
                                           *samples.clipOf, *samples.frameOf);
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
  m_pattern = pattern;
  m_patternPaths = paths;
  // The first label the pattern names colours the map.
  return setColorBy(QString::fromStdString(m_nameLabels.columns.front().name));
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
    m_nameLabels = {};
    m_pattern.clear();
    m_patternPaths.clear();
  } else if (!m_pattern.isEmpty()) {
    const MapSource::Samples samples = source->samples();
    if (samples.clipOf && samples.frameOf) {
      try {
        std::vector<std::string> names;
        for (const QString& path : m_patternPaths) names.push_back(path.toStdString());
        m_nameLabels = pipeline::sample_labels(
            pipeline::labels_from_names(names, pipeline::NamePattern(m_pattern.toStdString())),
            *samples.clipOf, *samples.frameOf);
      } catch (const std::exception&) {
        m_nameLabels = {};
      }
    }
  }
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
