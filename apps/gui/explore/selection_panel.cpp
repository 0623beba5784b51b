#include "explore/selection_panel.h"

#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTreeWidget>
#include <QVBoxLayout>

#include "map/map_source.h"
#include "map/map_view.h"
#include "playback/playback.h"

namespace motionmap::studio {

namespace {
constexpr int kRangeRole = Qt::UserRole + 1;  ///< an item's index into ranges()
}

SelectionPanel::SelectionPanel(MapView* view, Playback* playback,
                               std::function<const MapSource*()> source,
                               std::function<void(int, int)> showClip, QWidget* parent)
    : QDockWidget(tr("Selection"), parent),
      m_view(view),
      m_playback(playback),
      m_source(std::move(source)),
      m_showClip(std::move(showClip)) {
  setObjectName(QStringLiteral("selectionPanel"));
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  m_summary = new QLabel;
  m_summary->setWordWrap(true);
  layout->addWidget(m_summary);
  m_tree = new QTreeWidget;
  m_tree->setColumnCount(2);
  m_tree->setHeaderLabels({tr("Clip / frames"), tr("Frames")});
  m_tree->header()->setSectionResizeMode(0, QHeaderView::Stretch);
  m_tree->header()->setStretchLastSection(false);
  m_tree->setToolTip(tr("Double-click a range (or a clip) to play it"));
  layout->addWidget(m_tree, 1);
  auto* buttons = new QHBoxLayout;
  m_playAll = new QPushButton(tr("Play all"));
  m_playAll->setToolTip(tr("Plays every range listed, one after another"));
  m_exportList = new QPushButton(tr("Export list…"));
  m_exportList->setToolTip(tr("Writes the clips as a clip list: motionmap map @list.txt"));
  m_exportCsv = new QPushButton(tr("Export CSV…"));
  m_exportCsv->setToolTip(tr("Writes the frames as CSV: clip, frame, x, y"));
  auto* clearButton = new QPushButton(tr("Clear"));
  clearButton->setToolTip(tr("Clears the selection (also a right click on the map)"));
  toggleViewAction()->setToolTip(
      tr("Shows or hides the frames selected on the map (right drag: a box, Shift+right drag: a "
         "lasso)"));
  for (QPushButton* b : {m_playAll, m_exportList, m_exportCsv, clearButton}) {
    b->setFocusPolicy(Qt::NoFocus);  // Space and the arrows stay the window's
    buttons->addWidget(b);
  }
  layout->addLayout(buttons);
  setWidget(body);

  connect(view, &MapView::selectionDrawn, this, &SelectionPanel::select);
  connect(view, &MapView::mapReplaced, this, [this] {
    if (!m_frames.empty()) clear();
  });
  connect(m_playAll, &QPushButton::clicked, this,
          [this] { m_sequence ? stopSequence() : playAll(); });
  connect(m_exportList, &QPushButton::clicked, this, [this] { chooseAndExport(true); });
  connect(m_exportCsv, &QPushButton::clicked, this, [this] { chooseAndExport(false); });
  connect(clearButton, &QPushButton::clicked, this, &SelectionPanel::clear);
  connect(m_tree, &QTreeWidget::itemDoubleClicked, this, [this](QTreeWidgetItem* item) {
    stopSequence();
    playRange(item->data(0, kRangeRole).toInt());
  });
  m_wait.setInterval(40);
  connect(&m_wait, &QTimer::timeout, this, &SelectionPanel::startWhenShown);
  connect(playback, &Playback::playingChanged, this, &SelectionPanel::onPlayingChanged);
  rebuild();
}

void SelectionPanel::select(const QPolygonF& polygon) {
  stopSequence();
  const MapSource* source = m_source();
  m_frames = source ? framesInside(polygon, source->samples(),
                                   [this](int sample) { return m_view->sampleShown(sample); })
                    : std::vector<SelectedFrame>{};
  m_ranges = frameRanges(m_frames);
  Eigen::MatrixXd points(Eigen::Index(m_frames.size()), 2);
  for (std::size_t i = 0; i < m_frames.size(); ++i)
    points.row(Eigen::Index(i)) << m_frames[i].x, m_frames[i].y;
  m_view->setSelection(points, m_frames.empty() ? QPolygonF() : polygon);
  rebuild();
  if (!m_frames.empty()) {
    show();
    raise();
  }
  emit message(m_summary->text());
}

void SelectionPanel::clear() {
  stopSequence();
  m_frames.clear();
  m_ranges.clear();
  m_view->setSelection(Eigen::MatrixXd(0, 2), {});
  rebuild();
}

void SelectionPanel::rebuild() {
  m_tree->clear();
  const MapSource* source = m_source();
  const QStringList paths = source ? source->clipPaths() : QStringList();
  QTreeWidgetItem* clipItem = nullptr;
  int clip = -1, clips = 0;
  for (std::size_t i = 0; i < m_ranges.size(); ++i) {
    const FrameRange& r = m_ranges[i];
    if (r.clip != clip) {
      clip = r.clip;
      ++clips;
      clipItem = new QTreeWidgetItem(m_tree);
      clipItem->setText(
          0, tr("clip %1: %2").arg(clip + 1).arg(QFileInfo(paths.value(clip)).fileName()));
      clipItem->setToolTip(0, paths.value(clip));
      clipItem->setData(0, kRangeRole, int(i));
      clipItem->setExpanded(true);
    }
    auto* item = new QTreeWidgetItem(clipItem);
    item->setText(0, r.first == r.last ? tr("frame %1").arg(r.first)
                                       : tr("frames %1–%2").arg(r.first).arg(r.last));
    item->setText(1, QString::number(r.frames()));
    item->setData(0, kRangeRole, int(i));
    int total = clipItem->text(1).toInt() + r.frames();
    clipItem->setText(1, QString::number(total));
  }
  m_summary->setText(m_frames.empty()
                         ? tr("No selection: right-drag a box on the map, Shift+right-drag a "
                              "lasso.")
                         : tr("%1 frames of %2, %3 ranges")
                               .arg(m_frames.size())
                               .arg(clips == 1 ? tr("1 clip") : tr("%1 clips").arg(clips))
                               .arg(m_ranges.size()));
  for (QPushButton* b : {m_playAll, m_exportList, m_exportCsv}) b->setEnabled(!m_frames.empty());
}

void SelectionPanel::playRange(int index) {
  if (index < 0 || index >= int(m_ranges.size())) return;
  m_playing = index;
  m_started = false;
  const FrameRange& r = m_ranges[std::size_t(index)];
  m_playback->pause();
  m_showClip(r.clip, r.first);
  startWhenShown();
  if (m_playing == index && !m_started) m_wait.start();  // its clip is loading
}

void SelectionPanel::startWhenShown() {
  if (m_playing < 0) return m_wait.stop();
  const FrameRange& r = m_ranges[std::size_t(m_playing)];
  const MapSource* source = m_source();
  if (source && !source->isLoadingClip() && source->currentClip() != r.clip) {
    stopSequence();  // the clip could not be shown (the window said why)
    return;
  }
  if (!source || source->isLoadingClip() || !source->clip())
    return;  // not yet (a saved map's clip loading); the timer asks again
  m_wait.stop();
  m_started = true;
  m_playback->clearInPoint();
  m_playback->clearOutPoint();
  m_playback->setOutPoint(r.last);
  m_playback->setInPoint(r.first);
  m_playback->setFrame(r.first);
  m_playback->setLoop(false);
  emit message(tr("Playing clip %1, frames %2–%3").arg(r.clip + 1).arg(r.first).arg(r.last));
  if (r.first == r.last) {  // one frame: shown a moment, then the next
    QTimer::singleShot(400, this, [this, index = m_playing] {
      if (m_playing == index) onPlayingChanged(false);
    });
    return;
  }
  m_playback->play();
}

void SelectionPanel::onPlayingChanged(bool playing) {
  if (playing || m_playing < 0 || !m_started) return;
  const FrameRange& r = m_ranges[std::size_t(m_playing)];
  const bool reachedEnd = m_playback->frame() >= r.last;
  if (m_sequence && reachedEnd && m_playing + 1 < int(m_ranges.size())) {
    playRange(m_playing + 1);
    return;
  }
  // The end of one range or of all, or paused by the user.
  const bool wasSequence = m_sequence;
  m_sequence = false;
  m_playing = -1;
  m_playAll->setText(tr("Play all"));
  if (wasSequence) m_playback->setLoop(m_loopBefore);
}

void SelectionPanel::playAll() {
  if (m_ranges.empty()) return;
  m_loopBefore = m_playback->loop();
  m_sequence = true;
  m_playAll->setText(tr("Stop"));
  playRange(0);
}

void SelectionPanel::stopSequence() {
  m_wait.stop();
  if (m_playing >= 0) m_playback->pause();
  if (m_sequence) m_playback->setLoop(m_loopBefore);
  m_sequence = false;
  m_playing = -1;
  m_playAll->setText(tr("Play all"));
}

namespace {
bool writeText(const QString& path, const QString& text, QString* error) {
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate | QIODevice::Text) ||
      file.write(text.toUtf8()) < 0 || !file.flush()) {
    if (error) *error = QObject::tr("cannot write %1: %2").arg(path, file.errorString());
    return false;
  }
  return true;
}
}  // namespace

bool SelectionPanel::exportList(const QString& path, QString* error) const {
  const MapSource* source = m_source();
  if (!source || m_ranges.empty()) {
    if (error) *error = tr("Nothing is selected");
    return false;
  }
  QStringList files;
  for (int c = 0; c < source->clipCount(); ++c) files << source->clipFile(c);
  return writeText(path, clipListText(m_ranges, files, tr("the map shown")), error);
}

bool SelectionPanel::exportCsv(const QString& path, QString* error) const {
  const MapSource* source = m_source();
  if (!source || m_frames.empty()) {
    if (error) *error = tr("Nothing is selected");
    return false;
  }
  QStringList files;
  for (int c = 0; c < source->clipCount(); ++c) files << source->clipFile(c);
  return writeText(path, selectionCsv(m_frames, files), error);
}

void SelectionPanel::chooseAndExport(bool list) {
  const QString path = QFileDialog::getSaveFileName(
      this, list ? tr("Export the selection as a clip list") : tr("Export the selection as CSV"),
      list ? QStringLiteral("selection.txt") : QStringLiteral("selection.csv"),
      list ? tr("Clip lists (*.txt)") : tr("CSV (*.csv)"));
  if (path.isEmpty()) return;
  QString error;
  if (list ? exportList(path, &error) : exportCsv(path, &error)) {
    emit message(tr("Wrote %1").arg(path));
  } else {
    emit failed(error);
  }
}

}  // namespace motionmap::studio
