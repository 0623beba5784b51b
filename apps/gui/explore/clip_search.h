#pragma once
// The search box for clip names (a toolbar field, Ctrl+F): the clips whose file path contains the
// text typed (case-insensitive; several words: each must occur) are highlighted on the map
// (MapView::setHighlight, magenta) and counted beside it; Enter loads the first match, Enter
// again the next one (after the clip playing, wrapping around); Escape clears the text and the
// highlight. A new map shown keeps the search: its matches are highlighted again.
#include <functional>
#include <vector>

#include <QLineEdit>

class QLabel;
class QMainWindow;

namespace motionmap::studio {

class MapSource;
class MapView;

class ClipSearch : public QLineEdit {
  Q_OBJECT
 public:
  /// Highlights on `view`; `source` gives the map shown (it changes with File → Open map). Both
  /// must outlive this.
  ClipSearch(MapView* view, std::function<const MapSource*()> source, QWidget* parent = nullptr);
  /// A search field in a toolbar of `window`, with its count, and Ctrl+F to type in it.
  static ClipSearch* addTo(QMainWindow* window, MapView* view,
                           std::function<const MapSource*()> source);
  /// The matching clips (indices into the map's clips), in the map's order.
  const std::vector<int>& matches() const { return m_matches; }
  /// "3 clips" / "no clip" / empty: the count shown beside the field.
  QLabel* countLabel() const { return m_count; }
  /// The clip Enter loads now: the first match, or, when `current` is one, the next match after
  /// it (wrapping); −1 without matches.
  int nextMatch(int current) const;
  /// Whether clip path `path` matches `text` (each of its words occurs, case-insensitive).
  static bool matchesText(const QString& path, const QString& text);

 signals:
  /// Enter: play clip `clip` from its first frame.
  void clipRequested(int clip, int frame);

 protected:
  void keyPressEvent(QKeyEvent* event) override;

 private:
  /// Matches and highlight for the text and the map shown now.
  void refresh();

  MapView* m_view;
  std::function<const MapSource*()> m_source;
  std::vector<int> m_matches;
  QLabel* m_count;
};

}  // namespace motionmap::studio
