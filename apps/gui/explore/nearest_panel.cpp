#include "explore/nearest_panel.h"

#include <QFileInfo>
#include <QHeaderView>
#include <QTreeWidget>

#include "map/map_source.h"
#include "map/map_view.h"

namespace motionmap::studio {

NearestPanel::NearestPanel(MapView* view, std::function<const MapSource*()> source,
                           std::function<void(int, int)> showClip, QWidget* parent)
    : QDockWidget(tr("Nearest frames"), parent),
      m_view(view),
      m_source(std::move(source)),
      m_showClip(std::move(showClip)) {
  setObjectName(QStringLiteral("nearestPanel"));
  m_tree = new QTreeWidget;
  m_tree->setRootIsDecorated(false);
  m_tree->setColumnCount(3);
  m_tree->setHeaderLabels({tr("Clip"), tr("Frame"), tr("Distance")});
  m_tree->header()->setSectionResizeMode(0, QHeaderView::Stretch);
  m_tree->header()->setStretchLastSection(false);
  m_tree->setToolTip(
      tr("The frames of other clips nearest the point under the mouse on the map; "
         "click one to play its clip from there"));
  setWidget(m_tree);
  toggleViewAction()->setToolTip(
      tr("Lists the frames of other clips nearest the point under the mouse on the map, each "
         "one click away"));
  connect(view, &MapView::hovered, this, [this](const Eigen::Vector2d& point, const QPointF&) {
    if (isVisible()) showAround(point);
  });
  connect(view, &MapView::mapReplaced, this, [this] {
    m_entries.clear();
    m_tree->clear();
  });
  connect(m_tree, &QTreeWidget::itemClicked, this, [this](QTreeWidgetItem* item) {
    const int row = m_tree->indexOfTopLevelItem(item);
    if (row >= 0 && row < int(m_entries.size()))
      m_showClip(m_entries[std::size_t(row)].clip, m_entries[std::size_t(row)].frame);
  });
}

void NearestPanel::showAround(const Eigen::Vector2d& point) {
  m_entries.clear();
  const MapSource* source = m_source();
  const MapSource::Samples samples = source ? source->samples() : MapSource::Samples{};
  if (samples.clipOf && samples.frameOf) {
    const int current = source->currentClip();
    std::vector<char> listed(std::size_t(source->clipCount()), 0);
    // Frames a colouring by label hides are not offered (more are searched past them).
    const int searched = m_view->hidesSamples() ? kSearched * 16 : kSearched;
    for (const MapSource::Near& n : source->nearestSamples(point, searched)) {
      if (!m_view->sampleShown(n.sample)) continue;
      const int clip = (*samples.clipOf)[std::size_t(n.sample)];
      if (clip == current || clip < 0 || clip >= int(listed.size()) || listed[std::size_t(clip)])
        continue;
      listed[std::size_t(clip)] = 1;  // its nearest frame only: nearest first
      m_entries.push_back({clip, (*samples.frameOf)[std::size_t(n.sample)], n.distance});
      if (int(m_entries.size()) == kEntries) break;
    }
  }
  const QStringList paths = source ? source->clipPaths() : QStringList();
  m_tree->clear();
  for (const Entry& e : m_entries) {
    auto* item = new QTreeWidgetItem(m_tree);
    item->setText(0,
                  tr("clip %1: %2").arg(e.clip + 1).arg(QFileInfo(paths.value(e.clip)).fileName()));
    item->setText(1, QString::number(e.frame));
    item->setText(2, QString::number(e.distance, 'g', 3));
    item->setToolTip(0, paths.value(e.clip));
  }
}

}  // namespace motionmap::studio
