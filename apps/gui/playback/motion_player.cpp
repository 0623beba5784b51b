#include "playback/motion_player.h"

#include "map/map_source.h"
#include "map/map_view.h"
#include "playback/playback.h"
#include "scene/skeleton_view.h"
#include "takes/takes_controller.h"

namespace motionmap::studio {

MotionPlayer::MotionPlayer(Playback* playback, SkeletonView* skeletonView, MapView* mapView,
                           TakesController* takes, std::function<MapSource*()> source,
                           std::function<const MapResult*()> map, QObject* parent)
    : QObject(parent),
      m_playback(playback),
      m_skeletonView(skeletonView),
      m_mapView(mapView),
      m_takes(takes),
      m_source(std::move(source)),
      m_map(std::move(map)) {
  connect(m_playback, &Playback::frameChanged, this, &MotionPlayer::showFrame);
  connect(&m_takes->list(), &TakeList::currentMotionChanged, this, &MotionPlayer::playCurrentTake);
}

const synth::SynthResult* MotionPlayer::synthesized() const {
  const Take* take = m_takes->list().currentTake();
  return take ? take->result.get() : nullptr;
}

const Motion* MotionPlayer::playingMotion() const {
  if (m_playsTake && synthesized()) return &synthesized()->motion;
  const Clip* clip = m_source()->clip();
  return clip ? &clip->motion : nullptr;
}

bool MotionPlayer::playClip(int index, int frame) {
  if (!m_source()->selectClip(index, frame)) return false;  // out of range, failed, or loading
  m_playsTake = false;
  m_takes->list().setCurrent(-1);  // the clip plays: no take is current
  updateMotion();
  m_playback->setFrame(frame);
  return true;
}

void MotionPlayer::playCurrentTake() {
  const Take* take = m_takes->list().currentTake();
  emit takeShown(take != nullptr);
  if (!take) {
    // Its take is gone: the clip again.
    if (m_playsTake && playClip(m_source()->currentClip(), 0)) emit statusChanged();
    return;
  }
  m_playback->pause();
  m_playsTake = true;
  updateMotion();
  m_playback->setFrame(0);
  emit statusChanged();
  m_playback->play();
}

void MotionPlayer::stop() {
  m_playback->pause();
  m_playsTake = false;
}

QStringList MotionPlayer::statusParts() const {
  if (!m_playsTake || !synthesized()) return {};
  QStringList parts{tr("synthesized: %1 frames, %2 outside the data")
                        .arg(synthesized()->motion.num_frames)
                        .arg(synthesized()->clamped_frames)};
  // What the synthesis has to say (feet that slide or were not cleaned, legs that stalled).
  for (const std::string& note : synthesized()->notes) parts << QString::fromStdString(note);
  return parts;
}

void MotionPlayer::updateMotion() {
  const Motion* motion = playingMotion();
  m_playback->setMotion(motion ? motion->num_frames : 0, motion ? motion->frame_time : 0.0);
  emit motionShown(motion != nullptr);
  if (motion) m_skeletonView->setMotion(*motion);  // bones, clip bounds, trails
}

void MotionPlayer::showFrame(int frame) {
  const Motion* motion = playingMotion();
  if (!motion) return;
  m_skeletonView->setPose(*motion, frame);
  m_mapView->setPointer(m_playsTake && synthesized() ? m_takes->pointOn(m_map(), frame)
                                                     : m_source()->framePoint(frame));
  emit frameShown(frame);
}

}  // namespace motionmap::studio
