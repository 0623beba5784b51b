#include "playback/key_poses.h"

#include <algorithm>
#include <exception>

#include "map/map_source.h"
#include "motionmap/pipeline/key_poses.h"
#include "motionmap/skeleton/bones.h"

namespace motionmap::studio {

KeyPoses::KeyPoses(std::function<const MapSource*()> source, QObject* parent)
    : QObject(parent), m_source(std::move(source)) {}

KeyPoses::~KeyPoses() {
  m_job.stop();
}

void KeyPoses::setCount(int count) {
  count = std::clamp(count, kMinCount, kMaxCount);
  if (count == m_count) return;
  m_count = count;
  refresh();
}

void KeyPoses::setActive(bool active) {
  m_active = active;
  refresh();
}

int KeyPoses::indexOf(int frame) const {
  const auto it = std::find(m_frames.begin(), m_frames.end(), frame);
  return it == m_frames.end() ? -1 : int(it - m_frames.begin());
}

KeyPoses::Key KeyPoses::currentKey() const {
  Key key;
  key.count = m_count;
  const MapSource* source = m_source();
  key.source = source;
  if (!source) return key;
  const MapSource::Samples samples = source->samples();
  key.points = samples.points;
  key.rows = samples.points ? samples.points->rows() : 0;
  key.clipOf = samples.clipOf;
  key.clip = source->currentClip();
  key.data = source->clip();
  key.frames = key.data ? key.data->motion.num_frames : 0;
  return key;
}

void KeyPoses::refresh() {
  if (!m_active) return;
  const Key key = currentKey();
  if (m_valid && key == m_key) return;
  m_key = key;
  m_valid = true;
  start();
}

void KeyPoses::start() {
  m_job.stop();
  m_frames.clear();
  m_poses.clear();
  m_message.clear();
  m_clip = -1;
  const MapSource* source = m_key.source;
  m_map = source ? source->blendMap() : nullptr;
  if (!m_key.data) {
    m_message = tr("No clip: open one (File → Open)");
  } else if (!m_key.points || !m_key.clipOf) {
    m_message = tr("Key poses are picked from the clip's path on the map: waiting for the map");
  } else {
    const std::vector<int> rows = pipeline::clip_rows(*m_key.clipOf, m_key.clip);
    if (rows.size() < 2) {
      m_message =
          tr("The clip has %1 frame(s) on the map: key poses need 2 or more").arg(int(rows.size()));
    } else {
      // The clip's trajectory and its rows' frames, copied: the worker reads nothing shared.
      const Eigen::MatrixXd& all = *m_key.points;
      const std::vector<int>& frameOf = *source->samples().frameOf;
      Eigen::MatrixXd points(Eigen::Index(rows.size()), all.cols());
      std::vector<int> frames(rows.size());
      for (std::size_t i = 0; i < rows.size(); ++i) {
        points.row(Eigen::Index(i)) = all.row(rows[i]);
        frames[i] = frameOf[std::size_t(rows[i])];
      }
      m_up = source->upAxis();
      const int count = m_count;
      m_job.start([this, points = std::move(points), frames = std::move(frames),
                   count](const BackgroundJob::Ticket& ticket) {
        runJob<std::vector<int>>(
            this, m_job, ticket, [](double, const QString&) {},
            [&points, count](const Control&) {
              return std::make_shared<std::vector<int>>(pipeline::select_key_poses(points, count));
            },
            [this, frames](const JobOutcome<std::vector<int>>& outcome) {
              if (outcome.value) {
                finished(*outcome.value, frames);
              } else {
                m_message = outcome.error;
                emit changed();
              }
            });
      });
    }
  }
  emit changed();
}

void KeyPoses::finished(const std::vector<int>& keys, const std::vector<int>& frameOfRow) {
  if (!(currentKey() == m_key)) {  // the clip or the map changed without a refresh: again
    m_valid = false;
    refresh();
    return;
  }
  const Clip* clip = m_key.data;
  try {
    const std::vector<bool> detached = detached_joints(clip->skeleton, clip->motion);
    for (const int k : keys) {
      const int frame = frameOfRow[std::size_t(k)];
      m_frames.push_back(frame);
      m_poses.push_back(render::sheet_pose(clip->skeleton, clip->motion, detached, frame));
    }
    m_clip = m_key.clip;
  } catch (const std::exception& e) {
    m_frames.clear();
    m_poses.clear();
    m_message = QString::fromStdString(e.what());
  }
  emit changed();
}

}  // namespace motionmap::studio
