#include "map/clip_loader.h"

#include <QPointer>

#include "motionmap/mapfile/saved_map.h"

namespace motionmap::studio {

ClipLoader::ClipLoader(QObject* parent) : QObject(parent) {
  m_pool.setMaxThreadCount(1);
}

ClipLoader::~ClipLoader() {
  m_pool.clear();
  m_pool.waitForDone();
}

void ClipLoader::setMap(std::shared_ptr<const mapfile::SavedMap> map) {
  m_pool.clear();  // loads not yet started are dropped; a running one finishes unreported
  m_map = std::move(map);
  m_pending.clear();
  m_failed.clear();
}

std::optional<QString> ClipLoader::failure(int clip) const {
  const auto it = m_failed.find(clip);
  if (it == m_failed.end()) return std::nullopt;
  return it->second;
}

bool ClipLoader::request(int clip) {
  if (!m_map || clip < 0 || clip >= m_map->num_clips()) return false;
  if (m_map->is_loaded(clip)) return true;
  if (m_failed.count(clip) > 0) return false;        // failure() says why
  if (!m_pending.insert(clip).second) return false;  // already on its way
  std::shared_ptr<const mapfile::SavedMap> map = m_map;
  QPointer<ClipLoader> self(this);
  m_pool.start([map, clip, self] {
    QString error;
    try {
      map->clip(clip);  // into the map's cache
    } catch (const std::exception& e) {
      error = QString::fromStdString(e.what());
    }
    // Back on the loader's thread; dropped when the loader is gone or shows another map.
    QMetaObject::invokeMethod(
        self.data(),
        [self, map, clip, error] {
          if (!self || self->m_map != map) return;
          self->m_pending.erase(clip);
          if (error.isEmpty()) {
            emit self->loaded(clip);
          } else {
            self->m_failed[clip] = error;
            emit self->failed(clip, error);
          }
        },
        Qt::QueuedConnection);
  });
  return false;
}

}  // namespace motionmap::studio
