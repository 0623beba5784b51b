#include "explore/explore_panels.h"

#include <QAction>
#include <QActionGroup>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QLineEdit>
#include <QMainWindow>
#include <QMenu>

#include "explore/clip_search.h"
#include "explore/compare_panel.h"
#include "explore/legend_panel.h"
#include "explore/map_coloring.h"
#include "explore/nearest_panel.h"
#include "explore/selection_panel.h"
#include "map/map_controller.h"
#include "map/map_source.h"
#include "motionmap/mapfile/saved_map.h"

namespace motionmap::studio {

ExplorePanels::ExplorePanels(QMainWindow* window, MapView* view, SkeletonView* main3d,
                             Playback* playback, std::function<const MapSource*()> source,
                             const MapController* maps)
    : QObject(window), m_source(source), m_window(window) {
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
  // Colour by label: the legend beside the map while a label (or the clip) colours it.
  // A label file's spans are checked against the frames of each clip (as the CLI checks them).
  const auto clipFrames = [source, maps]() -> std::vector<int> {
    std::vector<int> frames;
    if (const auto* saved = dynamic_cast<const SavedMapSource*>(source())) {
      if (saved->map()) {
        for (const auto& clip : saved->map()->file().clips) frames.push_back(clip.frames);
      }
    } else if (const std::shared_ptr<const std::vector<Clip>> clips = maps->clips()) {
      for (const Clip& clip : *clips) frames.push_back(clip.motion.num_frames);
    }
    return frames;
  };
  m_coloring = new MapColoring(view, source, clipFrames, this);
  m_legend = new LegendPanel(m_coloring);
  window->addDockWidget(Qt::RightDockWidgetArea, m_legend);
  m_legend->hide();
  connect(m_coloring, &MapColoring::failed, this, &ExplorePanels::failed);
  connect(m_legend, &LegendPanel::labelFileRequested, this, &ExplorePanels::askLabelFile);
  // Two clips compared: a saved map's clip loaded (and checked) from its file, a computed map's
  // shared with the map.
  const auto clipOf = [source, maps](int c) -> std::shared_ptr<const Clip> {
    if (const auto* saved = dynamic_cast<const SavedMapSource*>(source()))
      return saved->map()->clip(c);
    const std::shared_ptr<const std::vector<Clip>> clips = maps->clips();
    if (!clips || c < 0 || c >= int(clips->size())) return nullptr;
    return std::shared_ptr<const Clip>(clips, &(*clips)[std::size_t(c)]);
  };
  m_compare = new ComparePanel(view, main3d, playback, source, clipOf);
  window->addDockWidget(Qt::LeftDockWidgetArea, m_compare);
  m_compare->hide();
  connect(m_compare, &ComparePanel::failed, this, &ExplorePanels::failed);
  QString before = m_coloring->colorBy();
  connect(m_coloring, &MapColoring::changed, this, [this, before]() mutable {
    const QString now = m_coloring->colorBy();
    if (now == before) return;
    before = now;
    if (now != MapColoring::timeChoice()) {
      m_legend->show();
      m_legend->raise();
    }
  });
}

void ExplorePanels::addViewActions(QMenu* view) {
  view->addAction(m_selection->toggleViewAction());
  view->addAction(m_nearest->toggleViewAction());
  QMenu* colourBy = view->addMenu(tr("Colour &by"));
  colourBy->setToolTipsVisible(true);
  // Its entries are the map's: made again each time it opens.
  connect(colourBy, &QMenu::aboutToShow, this, [this, colourBy] {
    colourBy->clear();
    auto* group = new QActionGroup(colourBy);
    for (const QString& name : m_coloring->choices()) {
      const QString text = name == MapColoring::timeChoice()   ? tr("Time")
                           : name == MapColoring::clipChoice() ? tr("Clip")
                                                               : name;
      QAction* a = colourBy->addAction(text, this, [this, name] { m_coloring->setColorBy(name); });
      a->setCheckable(true);
      a->setChecked(name == m_coloring->colorBy());
      group->addAction(a);
    }
    colourBy->addSeparator();
    colourBy->addAction(tr("Labels from file names…"), this, &ExplorePanels::askNamePattern)
        ->setToolTip(tr("Labels the clips of a map computed here by their file names, e.g. "
                        "{action}_{style}_{take} (as motionmap map --labels-from-name)"));
    colourBy->addAction(tr("Labels from file…"), this, &ExplorePanels::askLabelFile)
        ->setToolTip(tr("Labels the map's clips from a CSV or JSON file: a clip column and one "
                        "column per label, or clip,start,end,label spans (as motionmap map "
                        "--labels)"));
  });
  view->addAction(m_legend->toggleViewAction());
  view->addAction(tr("Compare with clip…"), this, &ExplorePanels::askCompare)
      ->setToolTip(tr("Plays another clip of the map with the one playing, in sync: its "
                      "character in the Compare dock or overlaid in the 3-D view, its trajectory "
                      "on the map"));
}

void ExplorePanels::askCompare() {
  const MapSource* source = m_source();
  if (!source || source->clipCount() < 2) {
    emit failed(tr("Comparing needs a map of two clips or more (File → Add clip, or a saved map)"));
    return;
  }
  QStringList names;
  for (const QString& path : source->clipPaths())
    names << tr("clip %1: %2").arg(names.size() + 1).arg(QFileInfo(path).fileName());
  bool ok = false;
  const QString chosen =
      QInputDialog::getItem(m_window, tr("Compare with clip"),
                            tr("The clip to play beside the one playing:"), names, 0, false, &ok);
  if (ok) m_compare->compareWith(int(names.indexOf(chosen)));
}

void ExplorePanels::askLabelFile() {
  const QString path = QFileDialog::getOpenFileName(
      m_window, tr("Labels from file"), QString(), tr("Label files (*.csv *.json);;All files (*)"));
  if (!path.isEmpty()) m_coloring->labelsFromFile(path);
}

void ExplorePanels::askNamePattern() {
  bool ok = false;
  const QString pattern = QInputDialog::getText(
      m_window, tr("Labels from file names"),
      tr("A pattern of the clips' file names, each {field} a label (e.g. "
         "{action}_{style}_{take}), or re: and a regular expression with named groups:"),
      QLineEdit::Normal, QStringLiteral("{action}_{style}_{take}"), &ok);
  if (ok) m_coloring->labelsFromNames(pattern);
}

}  // namespace motionmap::studio
