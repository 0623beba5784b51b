#include "playback/key_pose_strip.h"

#include <algorithm>
#include <exception>

#include <QAction>
#include <QHBoxLayout>
#include <QLabel>
#include <QMainWindow>
#include <QMouseEvent>
#include <QPainter>
#include <QScrollArea>
#include <QSettings>
#include <QSpinBox>
#include <QVBoxLayout>

#include "playback/key_poses.h"

namespace motionmap::studio {

namespace {

constexpr int kNumberHeight = 18;   // the pose's number above its figure
constexpr int kCaptionHeight = 34;  // "frame F" and "T s" under it
const char* const kShownKey = "keyPoses/shown";
const char* const kCountKey = "keyPoses/count";

}  // namespace

// ---- KeyPoseThumbnails ----

KeyPoseThumbnails::KeyPoseThumbnails(const KeyPoses* keys, QWidget* parent)
    : QWidget(parent), m_keys(keys) {
  setMinimumHeight(140);
  setMouseTracking(true);
  setToolTip(tr("Click a key pose to play the clip from its frame"));
}

QSize KeyPoseThumbnails::sizeHint() const {
  return {int(std::max<std::size_t>(m_keys->poses().size(), 1)) * kMinCell, 170};
}

int KeyPoseThumbnails::cellWidth() const {
  const int n = int(m_keys->poses().size());
  return n > 0 ? std::max(kMinCell, width() / n) : width();
}

QRect KeyPoseThumbnails::cellRect(int i) const {
  if (i < 0 || i >= int(m_keys->poses().size())) return {};
  return QRect(i * cellWidth(), 0, cellWidth(), height());
}

int KeyPoseThumbnails::indexAt(const QPoint& pos) const {
  for (int i = 0; i < int(m_keys->poses().size()); ++i) {
    if (cellRect(i).contains(pos)) return i;
  }
  return -1;
}

void KeyPoseThumbnails::setHighlighted(int index) {
  if (index == m_highlighted) return;
  m_highlighted = index;
  update();
}

void KeyPoseThumbnails::paintEvent(QPaintEvent* /*event*/) {
  QPainter p(this);
  p.fillRect(rect(), Qt::white);
  const std::vector<render::SheetPose>& poses = m_keys->poses();
  QFont font = p.font();
  font.setPixelSize(12);
  p.setFont(font);
  if (poses.empty()) {
    p.setPen(QColor(110, 110, 110));
    const QString text = m_keys->isComputing()          ? tr("Picking key poses…")
                         : !m_keys->message().isEmpty() ? m_keys->message()
                                                        : tr("No key poses");
    p.drawText(rect().adjusted(8, 0, -8, 0), Qt::AlignCenter | Qt::TextWordWrap, text);
    return;
  }
  std::vector<QRectF> figures;
  for (int i = 0; i < int(poses.size()); ++i) {
    const QRect cell = cellRect(i);
    if (i == m_highlighted) {
      p.fillRect(cell, QColor(255, 243, 214));
      p.setPen(QPen(QColor(230, 140, 0), 2.0));
      p.drawRect(QRectF(cell).adjusted(1, 1, -1, -1));
    }
    figures.emplace_back(QRectF(cell).adjusted(6, kNumberHeight + 2, -6, -kCaptionHeight));
  }
  try {
    render::paint_sheet_poses(p, figures, poses, static_cast<int>(m_keys->upAxis()));
  } catch (const std::exception& e) {
    p.setPen(Qt::red);
    p.drawText(rect(), Qt::AlignCenter, QString::fromStdString(e.what()));
    return;
  }
  QFont bold = font;
  bold.setBold(true);
  for (int i = 0; i < int(poses.size()); ++i) {
    const QRect cell = cellRect(i);
    p.setFont(bold);
    p.setPen(QColor(40, 40, 40));
    p.drawText(QRect(cell.left() + 6, cell.top() + 2, cell.width() - 12, kNumberHeight),
               Qt::AlignLeft | Qt::AlignVCenter, QString::number(i + 1));
    p.setFont(font);
    p.setPen(QColor(60, 60, 60));
    p.drawText(QRect(cell.left(), cell.bottom() - kCaptionHeight + 2, cell.width(), kCaptionHeight),
               Qt::AlignHCenter | Qt::AlignTop, poses[std::size_t(i)].caption);
    if (i + 1 < int(poses.size()) && i != m_highlighted && i + 1 != m_highlighted) {
      p.setPen(QPen(QColor(225, 225, 225), 1.0));
      p.drawLine(cell.right(), cell.top() + 8, cell.right(), cell.bottom() - 8);
    }
  }
}

void KeyPoseThumbnails::mousePressEvent(QMouseEvent* event) {
  if (event->button() != Qt::LeftButton) return QWidget::mousePressEvent(event);
  const int i = indexAt(event->position().toPoint());
  if (i >= 0) emit clicked(i);
}

// ---- KeyPoseStrip ----

KeyPoseStrip::KeyPoseStrip(QMainWindow* window, std::function<const MapSource*()> source,
                           std::function<bool()> clipPlays)
    : QDockWidget(tr("Key poses"), window), m_clipPlays(std::move(clipPlays)) {
  setObjectName(QStringLiteral("keyPoseStrip"));
  const QSettings settings;
  m_keys = new KeyPoses(std::move(source), this);
  m_keys->setCount(settings.value(kCountKey, KeyPoses::kDefaultCount).toInt());

  auto* body = new QWidget;
  auto* layout = new QHBoxLayout(body);
  layout->setContentsMargins(4, 2, 4, 4);
  auto* side = new QVBoxLayout;
  side->addWidget(new QLabel(tr("Poses")));
  m_count = new QSpinBox;
  m_count->setRange(KeyPoses::kMinCount, KeyPoses::kMaxCount);
  m_count->setValue(m_keys->count());
  m_count->setToolTip(
      tr("How many key poses: the first and last frames, and the frames whose "
         "points the clip's path on the map turns or changes speed at"));
  side->addWidget(m_count);
  side->addStretch(1);
  layout->addLayout(side);
  m_thumbnails = new KeyPoseThumbnails(m_keys);
  auto* scroll = new QScrollArea;
  scroll->setWidget(m_thumbnails);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setVerticalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  layout->addWidget(scroll, 1);
  setWidget(body);
  toggleViewAction()->setToolTip(
      tr("The clip's key poses under the views, picked from its path on the map; a click plays "
         "from one"));

  connect(m_count, &QSpinBox::valueChanged, this, [this](int count) {
    QSettings().setValue(kCountKey, count);
    m_keys->setCount(count);
  });
  connect(m_keys, &KeyPoses::changed, this, &KeyPoseStrip::updateView);
  connect(m_thumbnails, &KeyPoseThumbnails::clicked, this, [this](int i) {
    const std::vector<int>& frames = m_keys->frames();
    if (i >= 0 && i < int(frames.size()) && m_keys->clip() >= 0)
      emit clipRequested(m_keys->clip(), frames[std::size_t(i)]);
  });
  connect(this, &QDockWidget::visibilityChanged, m_keys, &KeyPoses::setActive);
  // Remembered when the user shows or hides it (not when the window closes).
  connect(toggleViewAction(), &QAction::triggered, this,
          [](bool shown) { QSettings().setValue(kShownKey, shown); });
  window->addDockWidget(Qt::BottomDockWidgetArea, this);
  setVisible(settings.value(kShownKey, false).toBool());
}

void KeyPoseStrip::showFrame(int frame) {
  m_frame = frame;
  m_keys->refresh();
  m_thumbnails->setHighlighted(m_clipPlays() ? m_keys->indexOf(frame) : -1);
}

void KeyPoseStrip::updateView() {
  m_thumbnails->setMinimumWidth(int(m_keys->poses().size()) * KeyPoseThumbnails::kMinCell);
  m_thumbnails->setHighlighted(m_clipPlays() && m_frame >= 0 ? m_keys->indexOf(m_frame) : -1);
  m_thumbnails->update();
}

}  // namespace motionmap::studio
