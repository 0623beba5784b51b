#pragma once
// Colour by label (View → Colour by): the map's samples drawn in the colours of a label's values
// — a saved map's labels (/labels of the map file), labels read from the clips' file names (a
// pattern, as `--labels-from-name`), or the clip each sample belongs to — with the CLI's palette
// and rule (render::category_color; up to kCategoryColors values each in its colour, in value
// order; with more, the kCategoryColors − 1 most frequent coloured and the others grey, as
// `motionmap map --color-by` draws them). Each value can be hidden, shown, or shown alone (solo):
// hidden samples are neither drawn nor picked (MapView::setSampleCategories). No widgets: the
// View menu and the legend (LegendPanel) drive it.
#include <functional>
#include <memory>
#include <vector>

#include <QColor>
#include <QObject>
#include <QString>
#include <QStringList>

#include "motionmap/pipeline/labels.h"

namespace motionmap::studio {

class MapSource;
class MapView;

class MapColoring : public QObject {
  Q_OBJECT
 public:
  /// The colourings that are not labels: each clip's time (the map's own colours) and the clip.
  static QString timeChoice() { return QStringLiteral("time"); }
  static QString clipChoice() { return QStringLiteral("clip"); }

  /// A value of the colouring: its name ("(none)" for unlabelled samples), its samples, its
  /// palette entry (render::category_color; −1 grey) and whether it is drawn.
  struct Entry {
    QString value;
    int count = 0;
    int category = -1;
    bool shown = true;
    QColor color() const;
  };

  /// Colours `view`'s map; `source` gives the source shown (its samples, clips and, for a saved
  /// map, its labels). Both must outlive this.
  MapColoring(MapView* view, std::function<const MapSource*()> source, QObject* parent = nullptr);

  /// timeChoice(), clipChoice() (a map of several clips) and the map's label names.
  QStringList choices() const;
  QString colorBy() const { return m_colorBy; }
  /// Colours by `name` (one of choices()), every value shown. False, with failed(), for a name
  /// the map does not have.
  bool setColorBy(const QString& name);
  /// The values of the colouring (none for time), in value order.
  const std::vector<Entry>& entries() const { return m_entries; }
  /// Entry `entry` drawn or hidden.
  void setShown(int entry, bool shown);
  /// Entry `entry` alone drawn; when it already is, every entry again.
  void solo(int entry);
  void showAll();
  /// Samples drawn (the counts of the shown entries).
  int shownSamples() const;
  /// Labels read from the clips' file names with `pattern` (pipeline::NamePattern, as
  /// `motionmap map --labels-from-name`), kept while the map's clips are the same: for maps
  /// computed here (a saved map has its own). False, with failed(), for a bad pattern or a name
  /// it does not match.
  bool labelsFromNames(const QString& pattern);

 signals:
  /// The colouring, its entries or which are shown changed.
  void changed();
  void failed(const QString& message);

 private:
  /// Another map is shown: its labels, and the colouring again when the map has it.
  void mapReplaced();
  /// Reads the values of m_colorBy into m_codes and m_entries (all shown).
  bool build();
  /// The view told each sample's category (hidden ones kHiddenCategory).
  void apply();
  const pipeline::Labels* labels() const;

  MapView* m_view;
  std::function<const MapSource*()> m_source;
  std::shared_ptr<const pipeline::Labels> m_savedLabels;  ///< a saved map's, or none
  pipeline::Labels m_nameLabels;                          ///< labelsFromNames'
  QString m_pattern;                                      ///< labelsFromNames' pattern
  QStringList m_patternPaths;                             ///< the clips it was read from
  QString m_colorBy = timeChoice();
  std::vector<int> m_codes;  ///< per sample: its entry
  std::vector<Entry> m_entries;
};

}  // namespace motionmap::studio
