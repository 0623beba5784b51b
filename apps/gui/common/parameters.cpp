#include "common/parameters.h"

#include <cmath>
#include <type_traits>

#include <QSettings>

namespace motionmap::studio {

namespace {

/// Sets `value` from the number at `key` when there is one that `valid` accepts.
template <class T, class Valid>
void readNumber(const QSettings& settings, const char* key, T& value, Valid valid) {
  bool ok = false;
  const double v = settings.value(key).toDouble(&ok);
  if (ok && std::isfinite(v) && valid(v)) value = static_cast<T>(v);
}

bool isCount(double v) {
  return v >= 1 && v <= 1e6 && v == std::floor(v);
}

std::string readName(const QSettings& settings, const char* key) {
  return settings.value(key).toString().toStdString();
}

QString fromName(std::string_view name) {
  return QString::fromUtf8(name.data(), qsizetype(name.size()));
}

}  // namespace

pipeline::ClipMapOptions MapParameters::options(embed::Method method) const {
  pipeline::ClipMapOptions o;
  o.embed.method = method;
  o.embed.k = k;
  o.embed.heat = heat;
  o.features.features = features;
  o.features.distance = distance;
  o.features.exclude = exclude;
  return o;
}

MapParameters readMapParameters(const QSettings& settings) {
  MapParameters m;
  readNumber(settings, "map/k", m.k, isCount);
  const QString heat = settings.value("map/heat").toString();
  bool heatOk = false;
  const double heatValue = heat.toDouble(&heatOk);
  if (heatOk && std::isfinite(heatValue)) m.heat = heatValue;  // "auto" (or nothing): automatic
  if (const auto f = features::parse_feature_kind(readName(settings, "map/features"))) {
    m.features = *f;
  }
  if (const auto d = features::parse_distance_kind(readName(settings, "map/distance"))) {
    m.distance = *d;
  }
  m.exclude = readName(settings, "map/exclude");
  return m;
}

SynthParameters readSynthParameters(const QSettings& settings) {
  SynthParameters s;
  if (const auto b = synth::parse_blend_mode(readName(settings, "synth/blend"))) s.blend.mode = *b;
  readNumber(settings, "synth/neighbors", s.blend.neighbors, isCount);
  readNumber(settings, "synth/reach", s.blend.reach, [](double v) { return v > 0; });
  s.timedAsDrawn = settings.value("synth/timedAsDrawn", true).toBool();
  s.freeRoots = settings.value("synth/freeRoots", false).toBool();
  synth::SynthOptions motion = s.motion;
  readNumber(settings, "synth/speed", motion.speed, [](double v) { return v >= 0; });
  readNumber(settings, "synth/fps", motion.fps, [](double v) { return v >= 0; });
  readNumber(settings, "synth/smooth", motion.smooth, [](double v) { return v >= 0; });
  try {
    motion.validate();
    s.motion = motion;
  } catch (const std::exception&) {
    // A combination the library rejects: the defaults stay.
  }
  return s;
}

void writeParameters(QSettings& settings, const MapParameters& m, const SynthParameters& s) {
  settings.setValue("map/k", m.k);
  settings.setValue("map/heat",
                    m.heat ? QString::number(*m.heat, 'g', 17) : QStringLiteral("auto"));
  settings.setValue("map/features", fromName(features::feature_kind_name(m.features)));
  settings.setValue("map/distance", fromName(features::distance_kind_name(m.distance)));
  settings.setValue("map/exclude", QString::fromStdString(m.exclude));
  settings.setValue("synth/blend", fromName(synth::blend_mode_name(s.blend.mode)));
  settings.setValue("synth/neighbors", s.blend.neighbors);
  settings.setValue("synth/reach", s.blend.reach);
  settings.setValue("synth/timedAsDrawn", s.timedAsDrawn);
  settings.setValue("synth/freeRoots", s.freeRoots);
  settings.setValue("synth/speed", s.motion.speed);
  settings.setValue("synth/fps", s.motion.fps);
  settings.setValue("synth/smooth", s.motion.smooth);
}

QString methodLabel(embed::Method method) {
  switch (method) {
    case embed::Method::Pca:
      return QStringLiteral("PCA");
    case embed::Method::Svd:
      return QStringLiteral("SVD");
    case embed::Method::Mds:
      return QStringLiteral("MDS");
    case embed::Method::Isomap:
      return QStringLiteral("Isomap");
    case embed::Method::LaplacianEigenmap:
      return QStringLiteral("LE");
    case embed::Method::Lle:
      return QStringLiteral("LLE");
    case embed::Method::Umap:
      return QStringLiteral("UMAP");
    case embed::Method::Gplvm:
      return QStringLiteral("GP-LVM");
  }
  return {};
}

}  // namespace motionmap::studio
