#include "explore/clip_search.h"

#include <algorithm>

#include <QAction>
#include <QKeyEvent>
#include <QLabel>
#include <QMainWindow>
#include <QToolBar>

#include "map/map_source.h"
#include "map/map_view.h"

namespace motionmap::studio {

ClipSearch::ClipSearch(MapView* view, std::function<const MapSource*()> source, QWidget* parent)
    : QLineEdit(parent), m_view(view), m_source(std::move(source)), m_count(new QLabel) {
  setPlaceholderText(tr("Find clips by name (Ctrl+F)"));
  setClearButtonEnabled(true);
  setToolTip(
      tr("Clips whose file name contains the words typed are highlighted on the map; "
         "Enter plays the first (again: the next), Escape clears"));
  setMaximumWidth(320);
  connect(this, &QLineEdit::textChanged, this, &ClipSearch::refresh);
  connect(view, &MapView::mapReplaced, this, &ClipSearch::refresh);
}

bool ClipSearch::matchesText(const QString& path, const QString& text) {
  const QStringList words = text.split(QLatin1Char(' '), Qt::SkipEmptyParts);
  if (words.isEmpty()) return false;
  for (const QString& word : words)
    if (!path.contains(word, Qt::CaseInsensitive)) return false;
  return true;
}

void ClipSearch::refresh() {
  m_matches.clear();
  const MapSource* source = m_source();
  const QString typed = text().trimmed();
  if (!source || typed.isEmpty()) {
    m_count->clear();
    if (m_view->highlight().rows() > 0) m_view->setHighlight(Eigen::MatrixXd(0, 2));
    return;
  }
  const QStringList paths = source->clipPaths();
  for (int c = 0; c < int(paths.size()); ++c)
    if (matchesText(paths[c], typed)) m_matches.push_back(c);
  std::vector<Eigen::MatrixXd> parts;
  Eigen::Index rows = 0;
  for (const int c : m_matches) {
    parts.push_back(source->clipPoints(c));
    rows += parts.back().rows();
  }
  Eigen::MatrixXd points(rows, 2);
  Eigen::Index at = 0;
  for (const Eigen::MatrixXd& part : parts) {
    points.middleRows(at, part.rows()) = part.leftCols(2);
    at += part.rows();
  }
  m_view->setHighlight(points);
  m_count->setText(m_matches.empty()       ? tr("no clip")
                   : m_matches.size() == 1 ? tr("1 clip")
                                           : tr("%1 clips").arg(m_matches.size()));
}

int ClipSearch::nextMatch(int current) const {
  if (m_matches.empty()) return -1;
  if (std::find(m_matches.begin(), m_matches.end(), current) == m_matches.end())
    return m_matches.front();  // the clip playing is no match: the first
  for (const int c : m_matches)
    if (c > current) return c;
  return m_matches.front();
}

void ClipSearch::keyPressEvent(QKeyEvent* event) {
  if (event->key() == Qt::Key_Escape) {
    clear();
    return;
  }
  if (event->key() == Qt::Key_Return || event->key() == Qt::Key_Enter) {
    const MapSource* source = m_source();
    const int clip = nextMatch(source ? source->currentClip() : -1);
    if (clip >= 0) emit clipRequested(clip, 0);
    return;
  }
  QLineEdit::keyPressEvent(event);
}

ClipSearch* ClipSearch::addTo(QMainWindow* window, MapView* view,
                              std::function<const MapSource*()> source) {
  auto* search = new ClipSearch(view, std::move(source));
  QToolBar* bar = window->addToolBar(tr("Find clips"));
  bar->setObjectName(QStringLiteral("findClipsBar"));
  bar->setMovable(false);
  bar->toggleViewAction()->setToolTip(tr("Shows or hides the clip search field"));
  bar->addWidget(search)->setToolTip(search->toolTip());
  bar->addWidget(search->countLabel())->setToolTip(tr("How many clips the search matches"));
  for (QAction* clear : search->findChildren<QAction*>())  // the field's clear button
    clear->setToolTip(tr("Clears the search and its highlight"));
  auto* find = new QAction(tr("Find clips"), window);
  find->setShortcut(QKeySequence::Find);
  find->setToolTip(
      tr("Puts the cursor in the clip search field (matching clips are highlighted "
         "on the map)"));
  connect(find, &QAction::triggered, search, [search] {
    search->setFocus(Qt::ShortcutFocusReason);
    search->selectAll();
  });
  window->addAction(find);
  return search;
}

}  // namespace motionmap::studio
