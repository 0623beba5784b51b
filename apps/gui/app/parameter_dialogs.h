#pragma once
// The two modal dialogs of the Motion menu: Parameters… (the map) and Synthesis… (drags and
// sketches). Each starts from the current values and returns what the user accepted; the library
// validates the values when they are applied, so the dialogs only keep them well-formed (and say
// the range of k the library accepts).
//
//   QString error;
//   if (auto p = editMapParameters(this, parameters(), frames, error)) setParameters(*p);
//   else if (!error.isEmpty()) showError(error);
#include <optional>

#include <QDialog>
#include <QString>

#include "common/parameters.h"

class QComboBox;
class QDialogButtonBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QSpinBox;
class QWidget;

namespace motionmap::studio {

/// Motion → Parameters…, starting from `now`. `frames` is the number of frames mapped (0: not
/// known yet), which bounds k: any k can be typed, and one outside the library's range
/// (motionmap/embed/k_range.h) is explained under the field, with OK disabled until it is valid.
class MapParametersDialog : public QDialog {
  Q_OBJECT
 public:
  MapParametersDialog(const MapParameters& now, int frames, QWidget* parent = nullptr);
  /// The parameters as edited; nothing (with `error` set) when the heat typed is not a number.
  std::optional<MapParameters> parameters(QString& error) const;
  QSpinBox* kField() const { return m_k; }
  /// The valid range of k and why, or why the k typed is out of it.
  QLabel* kHint() const { return m_kHint; }
  QPushButton* okButton() const;

 private:
  bool kValid() const;
  void checkK();

  int m_frames;
  QSpinBox* m_k;
  QLabel* m_kHint;
  QLineEdit* m_heat;
  QComboBox* m_features;
  QComboBox* m_distance;
  QLineEdit* m_exclude;
  QDialogButtonBox* m_buttons;
};

/// Runs MapParametersDialog over `parent`. The parameters as edited when the user pressed OK;
/// nothing on Cancel, or (with `error` set) when the heat typed is not a number.
std::optional<MapParameters> editMapParameters(QWidget* parent, const MapParameters& now,
                                               int frames, QString& error);

/// Runs the Motion → Synthesis dialog over `parent`, starting from `now`. The parameters as
/// edited when the user pressed OK; nothing on Cancel.
std::optional<SynthParameters> editSynthParameters(QWidget* parent, const SynthParameters& now);

}  // namespace motionmap::studio
