#pragma once
// The two modal dialogs of the Motion menu: Parameters… (the map) and Synthesis… (drags and
// sketches). Each starts from the current values and returns what the user accepted; the library
// validates the values when they are applied, so the dialogs only keep them well-formed.
//
//   QString error;
//   if (auto p = editMapParameters(this, parameters(), error)) setParameters(*p);
//   else if (!error.isEmpty()) showError(error);
#include <optional>

#include <QString>

#include "common/parameters.h"

class QWidget;

namespace motionmap::studio {

/// Runs the Motion → Parameters dialog over `parent`, starting from `now`. The parameters as
/// edited when the user pressed OK; nothing on Cancel, or (with `error` set) when the heat typed
/// is not a number.
std::optional<MapParameters> editMapParameters(QWidget* parent, const MapParameters& now,
                                               QString& error);

/// Runs the Motion → Synthesis dialog over `parent`, starting from `now`. The parameters as
/// edited when the user pressed OK; nothing on Cancel.
std::optional<SynthParameters> editSynthParameters(QWidget* parent, const SynthParameters& now);

}  // namespace motionmap::studio
