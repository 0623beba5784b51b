#include "takes/takes_panel.h"

#include <QAction>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QItemSelectionModel>
#include <QLabel>
#include <QListView>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QPushButton>
#include <QRegularExpression>
#include <QSettings>
#include <QShortcut>
#include <QVBoxLayout>

#include "takes/takes_controller.h"

namespace motionmap::studio {

TakesPanel::TakesPanel(TakesController* takes, QWidget* parent)
    : QDockWidget(tr("Takes"), parent), m_takes(takes) {
  setObjectName("takesPanel");
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  m_emptyHint = new QLabel(
      tr("No takes yet: Shift-drag on the map (or drag in View → Sketch mode) to sketch one."));
  m_emptyHint->setWordWrap(true);
  layout->addWidget(m_emptyHint);
  m_view = new QListView;
  m_view->setModel(&takes->list());
  m_view->setSelectionMode(QAbstractItemView::SingleSelection);
  m_view->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed);
  m_view->setToolTip(
      tr("Every sketch is a take. Select one to play it and edit its control points on the map; "
         "double-click (or F2) to rename; Delete removes it"));
  layout->addWidget(m_view, 1);
  auto* buttons = new QHBoxLayout;
  m_export = new QPushButton(tr("Export…"));
  m_export->setToolTip(tr("Write the selected take's motion as BVH"));
  m_delete = new QPushButton(tr("Delete"));
  m_delete->setToolTip(tr("Remove the selected take (Edit → Undo brings it back)"));
  buttons->addWidget(m_export);
  buttons->addWidget(m_delete);
  buttons->addStretch(1);
  layout->addLayout(buttons);
  setWidget(body);
  setToolTip(tr("The takes sketched on the maps of this clip"));

  // Delete acts on the list only, so the key stays free elsewhere (a text field, the map).
  auto* remove = new QShortcut(QKeySequence::Delete, m_view, nullptr, nullptr, Qt::WidgetShortcut);
  connect(remove, &QShortcut::activated, this, [this] { m_takes->remove(selectedRow()); });
  connect(m_delete, &QPushButton::clicked, this, [this] { m_takes->remove(selectedRow()); });
  connect(m_export, &QPushButton::clicked, this, [this] {
    const int row = selectedRow();
    if (row < 0) return;
    const QString path = QFileDialog::getSaveFileName(
        this, tr("Export take"), m_suggestion ? m_suggestion(row) : QString(), tr("BVH (*.bvh)"));
    if (!path.isEmpty()) emit exportRequested(row, path);
  });
  connect(m_view->selectionModel(), &QItemSelectionModel::currentRowChanged, this,
          [this](const QModelIndex& index) {
            // The view moves its current row when rows go: that is no choice of the user's.
            if (index.isValid() && !m_takes->list().removing())
              m_takes->list().setCurrent(index.row());
            updateButtons();
          });
  connect(&takes->list(), &TakeList::changed, this, &TakesPanel::syncSelection);
  updateButtons();
}

int TakesPanel::selectedRow() const {
  const QModelIndex index = m_view->selectionModel()->currentIndex();
  return index.isValid() ? index.row() : -1;
}

void TakesPanel::syncSelection() {
  // The list shows the current take selected (a new sketch, an undo) without selecting back.
  const int current = m_takes->list().current();
  if (current != selectedRow()) {
    const QSignalBlocker block(m_view->selectionModel());
    if (current >= 0) {
      m_view->selectionModel()->setCurrentIndex(m_takes->list().index(current),
                                                QItemSelectionModel::ClearAndSelect);
    } else {
      m_view->selectionModel()->clear();
    }
  }
  updateButtons();
}

void TakesPanel::updateButtons() {
  m_emptyHint->setVisible(m_takes->list().count() == 0);
  const bool selected = selectedRow() >= 0;
  m_export->setEnabled(selected);
  m_delete->setEnabled(selected);
}

QMenu* addEditMenu(QMainWindow* window, TakesController* takes, QDockWidget* panel) {
  QMenu* edit = window->menuBar()->addMenu(QMainWindow::tr("&Edit"));
  QUndoStack* stack = &takes->undoStack();
  QAction* undo = edit->addAction(QMainWindow::tr("&Undo"));
  undo->setShortcut(QKeySequence::Undo);
  undo->setEnabled(false);
  QObject::connect(undo, &QAction::triggered, takes, &TakesController::undo);
  QAction* redo = edit->addAction(QMainWindow::tr("&Redo"));
  redo->setShortcuts(
      {QKeySequence(QMainWindow::tr("Ctrl+Shift+Z")), QKeySequence(QMainWindow::tr("Ctrl+Y"))});
  redo->setEnabled(false);
  QObject::connect(redo, &QAction::triggered, takes, &TakesController::redo);
  // The entries say what they undo and redo ("Undo edit Take 2").
  auto update = [undo, redo, stack] {
    undo->setEnabled(stack->canUndo());
    redo->setEnabled(stack->canRedo());
    undo->setText(stack->canUndo() ? QMainWindow::tr("&Undo %1").arg(stack->undoText())
                                   : QMainWindow::tr("&Undo"));
    redo->setText(stack->canRedo() ? QMainWindow::tr("&Redo %1").arg(stack->redoText())
                                   : QMainWindow::tr("&Redo"));
    undo->setToolTip(undo->text().remove('&') + QMainWindow::tr(" (Ctrl+Z)"));
    redo->setToolTip(redo->text().remove('&') + QMainWindow::tr(" (Ctrl+Shift+Z or Ctrl+Y)"));
  };
  QObject::connect(stack, &QUndoStack::indexChanged, undo, update);
  QObject::connect(stack, &QUndoStack::cleanChanged, undo, update);
  update();
  edit->addSeparator();
  QAction* show = panel->toggleViewAction();
  show->setText(QMainWindow::tr("&Takes panel"));
  show->setToolTip(QMainWindow::tr("Show or hide the list of takes"));
  edit->addAction(show);
  return edit;
}

}  // namespace motionmap::studio
