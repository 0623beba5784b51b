#pragma once
// The clips of a saved map, loaded (and checked against the map file, as SavedMap::clip does) so
// that a map of another method or with other parameters can be computed from them: what
// "Recompute from clips…" does where a saved map, shown as it was made, cannot change.
#include <optional>
#include <vector>

#include <QString>

#include "motionmap/skeleton/skeleton.h"

class QWidget;

namespace motionmap::mapfile {
class SavedMap;
}
namespace motionmap::studio {

/// Every clip of `map` in the map's order, with a progress dialog over `parent` (none when
/// `parent` is null) whose Cancel gives nothing. @throws what SavedMap::clip throws (a clip
/// missing or changed since the map was made).
std::optional<std::vector<Clip>> loadSavedClips(const mapfile::SavedMap& map, QWidget* parent);

/// The question asked before: "lib.mmap.h5 is shown as it was made (…). A PCA map … needs its
/// 167 clips mapped again here: load them and compute it?"
QString recomputeQuestion(const mapfile::SavedMap& map, const QString& method);
/// Asks recomputeQuestion with the answers "Recompute from clips…" (true) and Cancel.
bool askRecompute(QWidget* parent, const mapfile::SavedMap& map, const QString& method);

}  // namespace motionmap::studio
