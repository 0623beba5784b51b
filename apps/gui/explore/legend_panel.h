#pragma once
// The legend of a colouring by label (MapColoring): a dock beside the map with the "Colour by"
// choice and one row per value — its colour, its name, its number of frames. A click on a row
// hides or shows that value; a Ctrl-click (or Alt-click, or the row's context menu → Solo) shows
// it alone, and again shows every value; "Show all" shows every value. Hidden values are drawn
// hollow and grey. "Labels from file…" asks for a label file (CSV or JSON) to colour by.
#include <QDockWidget>

class QComboBox;
class QLabel;
class QListWidget;
class QPushButton;

namespace motionmap::studio {

class MapColoring;

class LegendPanel : public QDockWidget {
  Q_OBJECT
 public:
  /// Shows and drives `coloring` (which must outlive this).
  explicit LegendPanel(MapColoring* coloring, QWidget* parent = nullptr);

  QListWidget* list() const { return m_list; }
  QComboBox* choice() const { return m_choice; }
  /// "12 345 of 20 000 frames shown".
  QLabel* summary() const { return m_summary; }
  QPushButton* showAllButton() const { return m_showAll; }
  QPushButton* labelFileButton() const { return m_labelFile; }
  /// What a click on row `row` does: Ctrl or Alt held → solo, else hide/show.
  void activate(int row, Qt::KeyboardModifiers modifiers);

 signals:
  /// "Labels from file…" was clicked: the window asks for the file.
  void labelFileRequested();

 protected:
  /// Keeps the modifiers of a press on the list (a click's solo or hide/show).
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  /// The rows and the choice again, from the colouring.
  void refresh();

  MapColoring* m_coloring;
  QComboBox* m_choice;
  QListWidget* m_list;
  QLabel* m_summary;
  QPushButton* m_showAll;
  QPushButton* m_labelFile;
  bool m_refreshing = false;
  Qt::KeyboardModifiers m_pressModifiers;  ///< of the last press on the list
};

}  // namespace motionmap::studio
