#pragma once
// The Takes dock, shown from the start so that its first take does not take room from the map
// (where the user is sketching): the list of takes (select one to play it, double-click or F2 to
// rename, Delete to remove it while the list has focus) with Export… and Delete buttons, and the
// Edit menu's Undo and Redo (Ctrl+Z; Ctrl+Shift+Z and Ctrl+Y), whose text says what they undo.
// Changes go through TakesController, so each is one step of its undo history.
#include <functional>

#include <QDockWidget>

class QLabel;
class QListView;
class QMainWindow;
class QMenu;
class QPushButton;

namespace motionmap::studio {

class TakesController;

class TakesPanel : public QDockWidget {
  Q_OBJECT
 public:
  explicit TakesPanel(TakesController* takes, QWidget* parent = nullptr);
  QListView* listView() const { return m_view; }
  /// Says how to sketch a take while there is none.
  QLabel* emptyHint() const { return m_emptyHint; }
  /// Where Export… suggests writing the take at `row` (the window's export folder and naming:
  /// "64_08-Take_1.bvh").
  void setSuggestion(std::function<QString(int row)> suggestion) {
    m_suggestion = std::move(suggestion);
  }

 signals:
  /// Export… chose `path` for the take at `row`.
  void exportRequested(int row, const QString& path);

 private:
  void syncSelection();
  int selectedRow() const;
  void updateButtons();

  TakesController* m_takes;
  QListView* m_view;
  QLabel* m_emptyHint;
  QPushButton* m_export;
  QPushButton* m_delete;
  std::function<QString(int)> m_suggestion;
};

/// Adds the Edit menu (Undo, Redo, and the Takes panel's toggle) to `window`'s menu bar; undo
/// and redo go through `takes` (TakesController::undo, redo).
QMenu* addEditMenu(QMainWindow* window, TakesController* takes, QDockWidget* panel);

}  // namespace motionmap::studio
