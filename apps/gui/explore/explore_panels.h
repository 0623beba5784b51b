#pragma once
// The window's tools for finding one's way in a map: the clip search bar (Ctrl+F), the Selection
// and Nearest docks (hidden until used), the colouring by label (MapColoring) with its Legend dock
// (shown when a label colours the map), the comparison of two clips (ComparePanel), made for a
// window and wired to its map view. The window
// connects clipRequested (play that clip from that frame), message and failed (its status line)
// and puts the docks' toggles and the Colour by menu in its View menu.
#include <functional>

#include <QObject>
#include <QString>

class QMainWindow;
class QMenu;

namespace motionmap::studio {

class MapSource;
class MapView;
class ComparePanel;
class LegendPanel;
class MapController;
class MapColoring;
class NearestPanel;
class Playback;
class SelectionPanel;
class SkeletonView;

class ExplorePanels : public QObject {
  Q_OBJECT
 public:
  /// Adds the search bar and the docks to `window`; `main3d` is its 3-D view (a compared clip
  /// overlaid there), `source` gives the map source shown, `maps` the clips of a map computed
  /// here. All must outlive this.
  ExplorePanels(QMainWindow* window, MapView* view, SkeletonView* main3d, Playback* playback,
                std::function<const MapSource*()> source, const MapController* maps);
  /// The docks' show/hide actions and the Colour by submenu (time, clip, each label of the map,
  /// Labels from file names… and Labels from file…), added to `view` (the View menu).
  void addViewActions(QMenu* view);
  MapColoring* coloring() const { return m_coloring; }
  LegendPanel* legend() const { return m_legend; }
  ComparePanel* compare() const { return m_compare; }
  /// View → Compare with clip…: a clip of the map asked for (ComparePanel::compareWith).
  void askCompare();
  /// View → Colour by → Labels from file names…: a pattern asked for
  /// (MapColoring::labelsFromNames).
  void askNamePattern();
  /// View → Colour by → Labels from file… (or the Legend's button): a CSV or JSON label file
  /// asked for (MapColoring::labelsFromFile).
  void askLabelFile();

 signals:
  /// A panel or the search asks to play clip `clip` from frame `frame`.
  void clipRequested(int clip, int frame);
  /// A line for the status bar.
  void message(const QString& text);
  /// An error to show.
  void failed(const QString& message);

 private:
  SelectionPanel* m_selection;
  NearestPanel* m_nearest;
  MapColoring* m_coloring;
  LegendPanel* m_legend;
  ComparePanel* m_compare;
  std::function<const MapSource*()> m_source;
  QMainWindow* m_window;
};

}  // namespace motionmap::studio
