#pragma once
// The Nearest frames panel (a dock, View → Nearest frames): while the mouse moves over the map,
// the frames of *other* clips nearest the point under it — the nearest frame of each clip, the
// closest clips first — listed as clip, frame and map distance; the list stays when the mouse
// leaves the map, and a click on an entry plays that clip from that frame. It answers "what else
// in the library looks like this?" one click away. Nothing is computed while the panel is hidden.
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <QDockWidget>

class QTreeWidget;

namespace motionmap::studio {

class MapSource;
class MapView;

class NearestPanel : public QDockWidget {
  Q_OBJECT
 public:
  /// Entries listed at most.
  static constexpr int kEntries = 10;
  /// Samples looked at around the point (their clips' nearest frames are listed).
  static constexpr int kSearched = 400;
  /// A frame listed.
  struct Entry {
    int clip = 0;
    int frame = 0;
    double distance = 0.0;
  };
  NearestPanel(MapView* view, std::function<const MapSource*()> source,
               std::function<void(int clip, int frame)> showClip, QWidget* parent = nullptr);
  /// Lists the nearest frames of other clips than the one playing around map point `point`
  /// (frames the view hides, MapView::sampleShown, left out).
  void showAround(const Eigen::Vector2d& point);
  const std::vector<Entry>& entries() const { return m_entries; }
  QTreeWidget* tree() const { return m_tree; }

 private:
  MapView* m_view;
  std::function<const MapSource*()> m_source;
  std::function<void(int, int)> m_showClip;
  std::vector<Entry> m_entries;
  QTreeWidget* m_tree;
};

}  // namespace motionmap::studio
