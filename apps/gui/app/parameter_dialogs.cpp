#include "app/parameter_dialogs.h"

#include <cmath>
#include <limits>

#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSpinBox>

#include "motionmap/embed/k_range.h"

namespace motionmap::studio {

namespace {

QString fromName(std::string_view name) {
  return QString::fromUtf8(name.data(), qsizetype(name.size()));
}

/// OK and Cancel as the form's last row; true when the dialog was accepted.
bool execWithButtons(QDialog& dialog, QFormLayout* form) {
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  form->addRow(buttons);
  QObject::connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
  QObject::connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  return dialog.exec() == QDialog::Accepted;
}

}  // namespace

MapParametersDialog::MapParametersDialog(const MapParameters& now, int frames, QWidget* parent)
    : QDialog(parent), m_frames(frames) {
  setWindowTitle(tr("Map parameters"));
  auto* form = new QFormLayout(this);
  // Any number can be typed (a field that stops at its bounds says nothing); one out of the
  // library's range (embed/k_range.h) is explained below the field, and OK waits for a valid k.
  m_k = new QSpinBox;
  m_k->setRange(0, std::numeric_limits<int>::max());
  m_k->setValue(now.k);
  m_k->setToolTip(
      tr("Neighbours per frame in the k-NN graph that Isomap, the Laplacian "
         "eigenmap and LLE build (too small: the graph falls apart)"));
  form->addRow(tr("Neighbours k (Isomap, LE, LLE)"), m_k);
  m_kHint = new QLabel;
  m_kHint->setWordWrap(true);
  form->addRow(QString(), m_kHint);
  m_heat = new QLineEdit(now.heat ? QString::number(*now.heat, 'g', 17) : QString());
  m_heat->setPlaceholderText(tr("auto"));
  m_heat->setToolTip(
      tr("Width t of the Laplacian eigenmap's heat kernel exp(−d²/t); "
         "empty: chosen from the data; ≤ 0: every edge weighs 1"));
  form->addRow(tr("Heat t (LE; ≤ 0: unit weights)"), m_heat);
  m_features = new QComboBox;
  for (auto f : features::all_feature_kinds()) {
    m_features->addItem(fromName(features::feature_kind_name(f)), int(f));
  }
  m_features->setCurrentIndex(m_features->findData(int(now.features)));
  m_features->setToolTip(
      tr("What a frame is as a vector: its joints' rotations as "
         "quaternions (quat) or their heading-local positions"));
  form->addRow(tr("Features (PCA, SVD, LLE)"), m_features);
  m_distance = new QComboBox;
  for (auto d : features::all_distance_kinds()) {
    m_distance->addItem(fromName(features::distance_kind_name(d)), int(d));
  }
  m_distance->setCurrentIndex(m_distance->findData(int(now.distance)));
  m_distance->setToolTip(
      tr("How far apart two poses are: the point clouds of their joints (pointcloud), "
         "the angles between their joints' rotations (geodesic), or the features"));
  form->addRow(tr("Distance (MDS, Isomap, LE)"), m_distance);
  m_exclude = new QLineEdit(QString::fromStdString(now.exclude));
  m_exclude->setPlaceholderText(tr("e.g. .*(Thumb|Finger).*"));
  m_exclude->setToolTip(
      tr("Joints whose names match this regular expression are left "
         "out of the features (e.g. fingers that flip)"));
  form->addRow(tr("Excluded joints (regex)"), m_exclude);
  m_buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  form->addRow(m_buttons);
  connect(m_buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(m_buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(m_k, &QSpinBox::valueChanged, this, &MapParametersDialog::checkK);
  checkK();
}

QPushButton* MapParametersDialog::okButton() const {
  return m_buttons->button(QDialogButtonBox::Ok);
}

bool MapParametersDialog::kValid() const {
  // Without a clip the frame count is not known: only the lower bound can be checked here.
  return m_frames > 0 ? embed::valid_neighbors(m_k->value(), m_frames)
                      : m_k->value() >= embed::kMinNeighbors;
}

void MapParametersDialog::checkK() {
  const QString range =
      m_frames > 0
          ? tr("k goes from %1 to %2: each of the map's %3 frames is joined to k of the other "
               "frames.")
                .arg(embed::kMinNeighbors)
                .arg(embed::max_neighbors(m_frames))
                .arg(m_frames)
          : tr("k is at least %1 and less than the number of frames mapped: each frame is joined "
               "to k of the other frames.")
                .arg(embed::kMinNeighbors);
  const bool valid = kValid();
  m_kHint->setText(valid ? range : tr("k = %1 is out of range. %2").arg(m_k->value()).arg(range));
  m_kHint->setStyleSheet(valid ? QString() : QStringLiteral("color: #c00000;"));
  okButton()->setEnabled(valid);
}

std::optional<MapParameters> MapParametersDialog::parameters(QString& error) const {
  MapParameters p;
  p.k = m_k->value();
  const QString heatText = m_heat->text().trimmed();
  if (!heatText.isEmpty() && heatText.compare("auto", Qt::CaseInsensitive) != 0) {
    bool ok = false;
    const double value = heatText.toDouble(&ok);
    if (!ok || !std::isfinite(value)) {
      error = tr("heat: '%1' is not a number (leave it empty for auto)").arg(heatText);
      return std::nullopt;
    }
    p.heat = value;
  }
  p.features = features::FeatureKind(m_features->currentData().toInt());
  p.distance = features::DistanceKind(m_distance->currentData().toInt());
  p.exclude = m_exclude->text().toStdString();
  return p;
}

std::optional<MapParameters> editMapParameters(QWidget* parent, const MapParameters& now,
                                               int frames, QString& error) {
  MapParametersDialog dialog(now, frames, parent);
  if (dialog.exec() != QDialog::Accepted) return std::nullopt;
  return dialog.parameters(error);
}

std::optional<SynthParameters> editSynthParameters(QWidget* parent, const SynthParameters& now) {
  QDialog dialog(parent);
  dialog.setWindowTitle(QDialog::tr("Synthesis"));
  auto* form = new QFormLayout(&dialog);
  auto* mode = new QComboBox;
  for (auto m : synth::all_blend_modes()) {
    mode->addItem(fromName(synth::blend_mode_name(m)), int(m));
  }
  mode->setCurrentIndex(mode->findData(int(now.blend.mode)));
  mode->setToolTip(QDialog::tr(
      "local: kriging on the K map-nearest samples (default); kriging: the reference system's "
      "rule over all samples (its set-up grows as N³: seconds at a few thousand frames, about "
      "half a minute at 10 000); idw: inverse-distance weights on the K nearest"));
  form->addRow(QDialog::tr("Blend"), mode);
  auto* neighbors = new QSpinBox;
  neighbors->setRange(1, 10000);
  neighbors->setValue(now.blend.neighbors);
  neighbors->setToolTip(QDialog::tr("How many map-nearest samples a local or idw blend uses"));
  form->addRow(QDialog::tr("Neighbours K (local, idw)"), neighbors);
  auto* reach = new QDoubleSpinBox;
  reach->setRange(0.01, 1000.0);
  reach->setDecimals(2);
  reach->setValue(now.blend.reach);
  reach->setToolTip(
      QDialog::tr("A point farther from every sample than reach × the median step between "
                  "consecutive samples is moved to the data's edge"));
  form->addRow(QDialog::tr("Reach (× median step)"), reach);
  auto* timing = new QComboBox;
  timing->addItem(QDialog::tr("as drawn"), true);
  timing->addItem(QDialog::tr("at a steady speed"), false);
  timing->setCurrentIndex(timing->findData(now.timedAsDrawn));
  timing->setToolTip(
      QDialog::tr("A sketch's motion takes as long as the gesture did (as "
                  "drawn), or runs along it at a steady speed"));
  form->addRow(QDialog::tr("Sketch timing"), timing);
  auto* speed = new QDoubleSpinBox;
  speed->setRange(0.0, 1e9);
  speed->setDecimals(4);
  speed->setSpecialValueText(QDialog::tr("the clip's"));
  speed->setValue(now.motion.speed);
  speed->setToolTip(
      QDialog::tr("Map units per second along a sketch at a steady speed; the clip's own "
                  "median speed at 0"));
  form->addRow(QDialog::tr("Steady speed"), speed);
  const auto enableSpeed = [timing, speed] { speed->setEnabled(!timing->currentData().toBool()); };
  enableSpeed();
  QObject::connect(timing, &QComboBox::currentIndexChanged, speed, enableSpeed);
  auto* fps = new QDoubleSpinBox;
  fps->setRange(0.0, 1000.0);
  fps->setDecimals(2);
  fps->setSpecialValueText(QDialog::tr("the clip's"));
  fps->setValue(now.motion.fps);
  fps->setToolTip(QDialog::tr("Frame rate of a synthesized motion; the clip's at 0"));
  form->addRow(QDialog::tr("Frames per second of the motion"), fps);
  auto* smooth = new QDoubleSpinBox;
  smooth->setRange(0.0, synth::kMaxSmoothSeconds);
  smooth->setDecimals(3);
  smooth->setSuffix(QDialog::tr(" s"));
  smooth->setSpecialValueText(QDialog::tr("none"));
  smooth->setValue(now.motion.smooth);
  smooth->setToolTip(QDialog::tr("σ of a Gaussian smoothing of the blend weights over time"));
  form->addRow(QDialog::tr("Smoothing"), smooth);
  auto* roots = new QComboBox;
  roots->addItem(QDialog::tr("placed at every key"), false);
  roots->addItem(QDialog::tr("free after the first key"), true);
  roots->setCurrentIndex(roots->findData(now.freeRoots));
  roots->setToolTip(
      QDialog::tr("An in-between's root stands where it stood in its clip at every key (keys of "
                  "takes captured in different places then make it glide), or at the first key "
                  "only, later keys' roots standing where the clips carry them"));
  form->addRow(QDialog::tr("In-between roots"), roots);
  if (!execWithButtons(dialog, form)) return std::nullopt;

  SynthParameters p = now;
  p.blend.mode = synth::BlendMode(mode->currentData().toInt());
  p.blend.neighbors = neighbors->value();
  p.blend.reach = reach->value();
  p.timedAsDrawn = timing->currentData().toBool();
  p.motion.speed = speed->value();
  p.motion.fps = fps->value();
  p.motion.smooth = smooth->value();
  p.freeRoots = roots->currentData().toBool();
  return p;
}

}  // namespace motionmap::studio
