#include "explore/compare_panel.h"

#include <algorithm>
#include <cmath>
#include <exception>

#include <QComboBox>
#include <QFileInfo>
#include <QLabel>
#include <QMainWindow>
#include <QPushButton>
#include <QVBoxLayout>

#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/skeleton/bones.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "playback/playback.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {

ComparePanel::ComparePanel(MapView* view, SkeletonView* main, Playback* playback,
                           std::function<const MapSource*()> source,
                           std::function<std::shared_ptr<const Clip>(int)> clipOf, QWidget* parent)
    : QDockWidget(tr("Compare"), parent),
      m_view(view),
      m_playback(playback),
      m_source(std::move(source)),
      m_clipOf(std::move(clipOf)),
      m_main(main) {
  setObjectName(QStringLiteral("comparePanel"));
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  m_caption = new QLabel;
  m_caption->setWordWrap(true);
  layout->addWidget(m_caption);
  m_placementChoice = new QComboBox;
  m_placementChoice->addItem(tr("Side by side"));
  m_placementChoice->addItem(tr("Overlaid, each at its place"));
  m_placementChoice->addItem(tr("Overlaid, roots together"));
  m_placementChoice->setToolTip(
      tr("Where the compared character is drawn: in its own view here, or in the main 3-D view "
         "over the one playing (translucent, in the comparison colour) — where its clip places "
         "it, or moved onto the playing character's root so the two poses coincide"));
  layout->addWidget(m_placementChoice);
  m_view3d = new SkeletonView;
  m_view3d->setMinimumSize(160, 160);
  layout->addWidget(m_view3d, 1);
  m_stop = new QPushButton(tr("Stop comparing"));
  m_stop->setToolTip(
      tr("Ends the comparison: the dock hides, the clip's trajectory leaves the map"));
  layout->addWidget(m_stop);
  layout->addStretch();  // overlaid (no view here): the controls at the top
  setWidget(body);
  toggleViewAction()->setToolTip(tr("The clip compared with the one playing, in sync"));
  connect(m_stop, &QPushButton::clicked, this, &ComparePanel::stop);
  connect(m_placementChoice, &QComboBox::activated, this,
          [this](int index) { setPlacement(Placement(index)); });
  // The main view shows another pose (or clip): an overlay together follows its root.
  connect(m_main, &SkeletonView::poseChanged, this, [this] {
    if (m_compared && m_placement == Placement::Together) drawOverlay();
  });
  connect(m_playback, &Playback::frameChanged, this, &ComparePanel::follow);
  connect(m_view, &MapView::mapReplaced, this, [this] {
    if (m_clip < 0) return;
    const MapSource* s = m_source();
    if (!s || m_clip >= s->clipCount() || !m_view->hasMap()) return stop();
    drawTrajectory();
    follow(m_playback->frame());
  });
}

bool ComparePanel::compareWith(int clip) {
  const MapSource* source = m_source();
  if (!source || clip < 0 || clip >= source->clipCount()) {
    emit failed(tr("There is no clip %1 to compare with (the map has %2)")
                    .arg(clip + 1)
                    .arg(source ? source->clipCount() : 0));
    return false;
  }
  std::shared_ptr<const Clip> loaded;
  try {
    loaded = m_clipOf(clip);
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
  if (!loaded || loaded->motion.num_frames < 1) {
    emit failed(tr("Clip %1 has no frames to compare").arg(clip + 1));
    return false;
  }
  m_compared = std::move(loaded);
  m_clip = clip;
  m_name = QFileInfo(source->clipPaths().value(clip)).fileName();
  m_view3d->setSkeleton(m_compared->skeleton);
  m_view3d->setMotion(m_compared->motion);
  m_detached = detached_joints(m_compared->skeleton, m_compared->motion);
  m_root = motion_root(m_compared->skeleton, m_compared->motion);
  drawTrajectory();
  show();
  raise();
  // Room for the character: a quarter of the window's width.
  auto* window = qobject_cast<QMainWindow*>(parentWidget());
  if (window && m_placement == Placement::SideBySide)
    window->resizeDocks({this}, {std::max(width(), window->width() / 4)}, Qt::Horizontal);
  follow(m_playback->frame());
  return true;
}

void ComparePanel::stop() {
  m_clip = -1;
  m_compared.reset();
  m_trajectory.resize(0, 2);
  m_rowOfFrame.clear();
  m_view->setComparison({}, std::nullopt);
  m_main->clearOverlay();
  m_shift.setZero();
  hide();
}

void ComparePanel::setPlacement(Placement placement) {
  m_placement = placement;
  m_placementChoice->setCurrentIndex(int(placement));
  m_view3d->setVisible(placement == Placement::SideBySide);
  // Overlaid, the dock needs room for its controls only; side by side, for the character.
  if (auto* window = qobject_cast<QMainWindow*>(parentWidget()); window && isVisible()) {
    const int wide = placement == Placement::SideBySide ? std::max(width(), window->width() / 4)
                                                        : minimumSizeHint().width();
    window->resizeDocks({this}, {wide}, Qt::Horizontal);
  }
  if (!m_compared) return;
  if (placement == Placement::SideBySide) m_view3d->setPose(m_compared->motion, m_frame);
  drawOverlay();
}

void ComparePanel::drawOverlay() {
  m_shift.setZero();
  if (!m_compared || m_placement == Placement::SideBySide) {
    m_main->clearOverlay();
    return;
  }
  WorldPose world = forward_kinematics(m_compared->skeleton, m_compared->motion, m_frame);
  const WorldPose& playing = m_main->worldPose();
  const int root = m_main->motionRoot();
  if (m_placement == Placement::Together && std::size_t(m_root) < world.positions.size() &&
      std::size_t(root) < playing.positions.size()) {
    // Its root's floor point onto the playing one's; heights stay.
    const Eigen::Vector3d d =
        playing.positions[std::size_t(root)] - world.positions[std::size_t(m_root)];
    m_shift = Eigen::Vector3d(d.x(), 0.0, d.z());
    for (Eigen::Vector3d& p : world.positions) p += m_shift;
  }
  m_main->setOverlay(m_compared->skeleton, world, m_detached, MapView::comparisonColor());
}

int ComparePanel::syncedFrame(int frame) const {
  if (!m_compared) return 0;
  // The same time from each clip's start, at each one's frame rate.
  const double dt = m_compared->motion.frame_time;
  const double t = frame * m_playback->frameTime();
  const int synced = dt > 0.0 ? int(std::lround(t / dt)) : frame;
  return std::clamp(synced, 0, m_compared->motion.num_frames - 1);
}

void ComparePanel::follow(int frame) {
  if (!m_compared) return;
  m_frame = syncedFrame(frame);
  if (m_placement == Placement::SideBySide) m_view3d->setPose(m_compared->motion, m_frame);
  drawOverlay();
  std::optional<Eigen::Vector2d> point;
  if (m_frame < int(m_rowOfFrame.size()) && m_rowOfFrame[std::size_t(m_frame)] >= 0) {
    const Eigen::Index row = m_rowOfFrame[std::size_t(m_frame)];
    point = Eigen::Vector2d(m_trajectory(row, 0), m_trajectory(row, 1));
  }
  m_view->setComparison(m_trajectory, point, m_clip);
  m_caption->setText(tr("clip %1: %2 · frame %3 of %4")
                         .arg(m_clip + 1)
                         .arg(m_name)
                         .arg(m_frame)
                         .arg(m_compared->motion.num_frames));
}

void ComparePanel::drawTrajectory() {
  const MapSource* source = m_source();
  m_trajectory = source ? source->clipPoints(m_clip) : Eigen::MatrixXd(0, 2);
  // Each frame's row among the clip's samples (a frame between samples: the sample before it).
  m_rowOfFrame.assign(std::size_t(m_compared ? m_compared->motion.num_frames : 0), -1);
  const MapSource::Samples samples = source ? source->samples() : MapSource::Samples{};
  if (samples.clipOf && samples.frameOf) {
    Eigen::Index row = 0;
    for (std::size_t i = 0; i < samples.clipOf->size(); ++i) {
      if ((*samples.clipOf)[i] != m_clip) continue;
      const int f = (*samples.frameOf)[i];
      if (row < m_trajectory.rows() && f >= 0 && f < int(m_rowOfFrame.size()))
        m_rowOfFrame[std::size_t(f)] = int(row);
      ++row;
    }
  }
  int last = -1;
  for (int& r : m_rowOfFrame) {
    if (r >= 0) {
      last = r;
    } else {
      r = last;
    }
  }
}

}  // namespace motionmap::studio
