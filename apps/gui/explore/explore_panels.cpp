#include "explore/explore_panels.h"

#include <QAction>
#include <QMainWindow>
#include <QMenu>

#include "explore/clip_search.h"
#include "explore/nearest_panel.h"
#include "explore/selection_panel.h"

namespace motionmap::studio {

ExplorePanels::ExplorePanels(QMainWindow* window, MapView* view, Playback* playback,
                             std::function<const MapSource*()> source)
    : QObject(window) {
  const auto request = [this](int clip, int frame) { emit clipRequested(clip, frame); };
  // Box and lasso selections of the map's frames, listed, played and exported (a dock, shown with
  // the first selection).
  m_selection = new SelectionPanel(view, playback, source, request);
  window->addDockWidget(Qt::RightDockWidgetArea, m_selection);
  m_selection->hide();
  connect(m_selection, &SelectionPanel::message, this, &ExplorePanels::message);
  connect(m_selection, &SelectionPanel::failed, this, &ExplorePanels::failed);
  m_nearest = new NearestPanel(view, source, request);
  window->addDockWidget(Qt::RightDockWidgetArea, m_nearest);
  m_nearest->hide();
  connect(ClipSearch::addTo(window, view, source), &ClipSearch::clipRequested, this,
          &ExplorePanels::clipRequested);
}

void ExplorePanels::addViewActions(QMenu* view) {
  view->addAction(m_selection->toggleViewAction());
  view->addAction(m_nearest->toggleViewAction());
}

}  // namespace motionmap::studio
