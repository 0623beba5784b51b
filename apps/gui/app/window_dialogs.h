#pragma once
// The window's questions: whether to drop takes that were not exported, and the key times of an
// in-between take (Motion → Retime Keys…). Each asks and returns the answer; the window acts on it.
#include <functional>
#include <optional>
#include <vector>

#include <QString>
#include <QStringList>

class QWidget;

namespace motionmap::studio {

struct Take;

/// Asks before the takes named `unexported` are dropped: Export… (a folder asked for, then
/// `exportTo(folder)` says whether they were written), Discard, or Cancel. True to go on (always
/// when `unexported` is empty).
bool askDiscard(QWidget* parent, const QStringList& unexported,
                const std::function<bool(const QString& folder)>& exportTo);

/// The key times of `take` (an in-between take with a motion), edited as text: seconds from the
/// first key, separated by commas, starting from its keys' times now. Nothing when cancelled;
/// else the times typed (empty: the frames' own speed along the route). A part that is not a
/// number: nothing, with `error` saying which.
std::optional<std::vector<double>> askKeyTimes(QWidget* parent, const Take& take, QString& error);

}  // namespace motionmap::studio
