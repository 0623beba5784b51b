#pragma once
// Clips of a saved map loaded on a worker thread, so that a click or a drag on a map of 10⁶ points
// never waits for a file: mapfile::SavedMap::clip() (SHA-256 check and parse) runs on the
// loader's own thread, and loaded() / failed() come back on the thread the loader lives in. The
// clip then sits in the SavedMap's cache, where the GUI thread takes it at once.
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <QObject>
#include <QString>
#include <QThreadPool>

namespace motionmap::mapfile {
class SavedMap;
}

namespace motionmap::studio {

class ClipLoader : public QObject {
  Q_OBJECT
 public:
  explicit ClipLoader(QObject* parent = nullptr);
  /// Waits for a load in progress (its result is dropped).
  ~ClipLoader() override;

  /// The map whose clips are loaded (nullptr: none). Loads requested for the map before are
  /// finished but not reported.
  void setMap(std::shared_ptr<const mapfile::SavedMap> map);
  /// True when clip `clip` is in the map's cache (use it now); otherwise starts loading it (once,
  /// however often asked) and returns false: loaded(clip) or failed(clip, message) follows.
  bool request(int clip);
  /// Loads started and not yet reported.
  int pending() const { return int(m_pending.size()); }
  /// The message of a load of `clip` that failed (it is not tried again for this map: open the
  /// map again after fixing the file), or nothing.
  std::optional<QString> failure(int clip) const;

 signals:
  void loaded(int clip);
  /// The library's message (the file missing, changed since the map was made, …).
  void failed(int clip, const QString& message);

 private:
  std::shared_ptr<const mapfile::SavedMap> m_map;
  std::set<int> m_pending;
  std::map<int, QString> m_failed;
  QThreadPool m_pool;  ///< one thread: loads run one after another, in the order asked
};

}  // namespace motionmap::studio
