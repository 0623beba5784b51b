#include "explore/legend_panel.h"

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QMenu>
#include <QMouseEvent>
#include <QPainter>
#include <QPixmap>
#include <QPushButton>
#include <QVBoxLayout>

#include "explore/map_coloring.h"

namespace motionmap::studio {

namespace {

/// A value's swatch: filled in its colour when shown, a grey outline when hidden.
QIcon swatch(const QColor& color, bool shown) {
  QPixmap pixmap(14, 14);
  pixmap.fill(Qt::transparent);
  QPainter p(&pixmap);
  p.setRenderHint(QPainter::Antialiasing);
  p.setPen(QPen(shown ? color.darker(130) : QColor(160, 160, 160), 1.5));
  p.setBrush(shown ? QBrush(color) : QBrush(Qt::NoBrush));
  p.drawRoundedRect(QRectF(1.5, 1.5, 11, 11), 2, 2);
  return QIcon(pixmap);
}

}  // namespace

LegendPanel::LegendPanel(MapColoring* coloring, QWidget* parent)
    : QDockWidget(tr("Legend"), parent), m_coloring(coloring) {
  setObjectName(QStringLiteral("legendPanel"));
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel(tr("Colour by")));
  m_choice = new QComboBox;
  m_choice->setToolTip(tr("What colours the map: each clip's time, the clip, or a label's values"));
  row->addWidget(m_choice, 1);
  layout->addLayout(row);
  m_list = new QListWidget;
  m_list->setSelectionMode(QAbstractItemView::NoSelection);
  m_list->setContextMenuPolicy(Qt::CustomContextMenu);
  m_list->setToolTip(
      tr("Click a value to hide or show its frames; Ctrl-click (or Alt-click) to show it alone, "
         "and again to show all"));
  layout->addWidget(m_list, 1);
  m_summary = new QLabel;
  layout->addWidget(m_summary);
  m_showAll = new QPushButton(tr("Show all"));
  m_showAll->setToolTip(tr("Shows the frames of every value"));
  m_labelFile = new QPushButton(tr("Labels from file…"));
  m_labelFile->setToolTip(
      tr("Colours the map by labels read from a CSV or JSON file (as motionmap map --labels)"));
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(m_showAll);
  buttons->addWidget(m_labelFile);
  layout->addLayout(buttons);
  setWidget(body);
  toggleViewAction()->setToolTip(
      tr("The colours of the map's values, each with its frames: hide, show or solo a value"));

  m_list->viewport()->installEventFilter(this);
  connect(m_choice, &QComboBox::textActivated, this, [this](const QString& name) {
    if (!m_refreshing) m_coloring->setColorBy(name);
  });
  connect(m_list, &QListWidget::itemClicked, this,
          [this](QListWidgetItem* item) { activate(m_list->row(item), m_pressModifiers); });
  connect(m_list, &QWidget::customContextMenuRequested, this, [this](const QPoint& at) {
    const int r = m_list->row(m_list->itemAt(at));
    if (r < 0) return;
    QMenu menu;
    menu.addAction(tr("Solo"), this, [this, r] { m_coloring->solo(r); });
    menu.addAction(m_coloring->entries()[std::size_t(r)].shown ? tr("Hide") : tr("Show"), this,
                   [this, r] { activate(r, Qt::NoModifier); });
    menu.addAction(tr("Show all"), m_coloring, &MapColoring::showAll);
    menu.exec(m_list->viewport()->mapToGlobal(at));
  });
  connect(m_showAll, &QPushButton::clicked, m_coloring, &MapColoring::showAll);
  connect(m_labelFile, &QPushButton::clicked, this, &LegendPanel::labelFileRequested);
  connect(m_coloring, &MapColoring::changed, this, &LegendPanel::refresh);
  refresh();
}

bool LegendPanel::eventFilter(QObject* watched, QEvent* event) {
  if (watched == m_list->viewport() && event->type() == QEvent::MouseButtonPress)
    m_pressModifiers = static_cast<QMouseEvent*>(event)->modifiers();
  return QDockWidget::eventFilter(watched, event);
}

void LegendPanel::activate(int row, Qt::KeyboardModifiers modifiers) {
  const auto& entries = m_coloring->entries();
  if (row < 0 || row >= int(entries.size())) return;
  if (modifiers & (Qt::ControlModifier | Qt::AltModifier)) return m_coloring->solo(row);
  m_coloring->setShown(row, !entries[std::size_t(row)].shown);
}

void LegendPanel::refresh() {
  m_refreshing = true;
  m_choice->clear();
  m_choice->addItems(m_coloring->choices());
  m_choice->setCurrentText(m_coloring->colorBy());
  m_refreshing = false;
  const auto& entries = m_coloring->entries();
  // Rows are kept (only their look changes) while the values are the same: a click stays put.
  if (m_list->count() != int(entries.size())) {
    m_list->clear();
    for (std::size_t e = 0; e < entries.size(); ++e) m_list->addItem(QString());
  }
  int total = 0;
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const MapColoring::Entry& entry = entries[e];
    QListWidgetItem* item = m_list->item(int(e));
    item->setText(tr("%1 (%2)").arg(entry.value).arg(entry.count));
    item->setIcon(swatch(entry.color(), entry.shown));
    item->setForeground(entry.shown ? palette().text() : QBrush(QColor(150, 150, 150)));
    QFont font = item->font();
    font.setStrikeOut(!entry.shown);
    item->setFont(font);
    total += entry.count;
  }
  m_summary->setText(entries.empty()
                         ? tr("Choose a label to colour the map by")
                         : tr("%1 of %2 frames shown").arg(m_coloring->shownSamples()).arg(total));
  m_showAll->setEnabled(m_coloring->shownSamples() < total);
}

}  // namespace motionmap::studio
