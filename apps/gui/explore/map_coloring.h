#pragma once
// Colour by label (View → Colour by): the map's samples drawn in the colours of a label's values
// — a saved map's labels (/labels of the map file), labels read from the clips' file names (a
// pattern, as `--labels-from-name`) or from a label file (CSV or JSON, as `--labels`), or the
// clip each sample belongs to — with the CLI's palette and rule (render::category_color and
// render::category_slots: up to kCategoryColors values each in its colour, in value order; with
// more, the kCategoryColors − 1 most frequent coloured and the others grey, as
// `motionmap map --color-by` draws them). Each value can be hidden, shown, or shown alone (solo):
// hidden samples are neither drawn nor picked (MapView::setSampleCategories). No widgets: the
// View menu and the legend (LegendPanel) drive it.
#include <functional>
#include <memory>
#include <span>
#include <string>
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
  /// `clipFrames` (optional) gives the frames of each clip of the map shown, which a label file's
  /// spans must lie within (as the CLI checks them).
  MapColoring(MapView* view, std::function<const MapSource*()> source,
              std::function<std::vector<int>()> clipFrames = {}, QObject* parent = nullptr);

  /// timeChoice(), clipChoice() (a map of several clips), the map's label names, then those of
  /// a label file not already among them.
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
  /// Labels read from the label file `path` (pipeline::read_label_file, as `motionmap map
  /// --labels`: a clip column and one column per label, or clip,start,end,label spans, or JSON;
  /// a clip named by its path, file name or stem), kept while the map's clips are the same: for
  /// computed and saved maps. The file's labels are merged into the map's (a saved map's, or
  /// those from the names) by the CLI's rule for `--labels-from-name … --labels`
  /// (pipeline::merge_labels): a label of the file with the name of one of the map's is that
  /// label, the file's values winning where its rows or spans cover frames and the map's staying
  /// elsewhere; its other labels are new. Colours by the file's first label. False, with failed()
  /// naming the file and the line, for a file that cannot be read or names a clip the map does not
  /// have.
  bool labelsFromFile(const QString& path);
  /// The label file read (empty: none).
  QString labelFile() const { return m_filePath; }
  /// The values of label `name` per sample of the map shown (nullptr: no such label): with a
  /// label file, the map's labels and the file's merged; else the saved map's or the names'.
  const pipeline::LabelColumn* column(const std::string& name) const;

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
  /// The map's labels before a file's: a saved map's (as a table of spans) or the names'.
  /// @throws ParameterError as pipeline::label_table().
  pipeline::LabelTable baseTable(std::span<const int> clipOf, std::span<const int> frameOf) const;
  /// `base` with `file`'s labels merged in (pipeline::merge_labels, as the CLI), per sample.
  /// @throws ParameterError as pipeline::merge_labels() and sample_labels().
  static pipeline::Labels withFile(pipeline::LabelTable base, const pipeline::LabelTable& file,
                                   const std::string& path, std::span<const int> clipOf,
                                   std::span<const int> frameOf);
  /// The file's labels merged into the map's and sampled on the map shown (none when it has
  /// other clips).
  void mergeFileLabels();

  MapView* m_view;
  std::function<const MapSource*()> m_source;
  std::shared_ptr<const pipeline::Labels> m_savedLabels;  ///< a saved map's, or none
  pipeline::LabelTable m_nameTable;                       ///< labelsFromNames', as read
  pipeline::Labels m_nameLabels;                          ///< m_nameTable per sample
  QString m_pattern;                                      ///< labelsFromNames' pattern
  QStringList m_patternPaths;                             ///< the clips it was read from
  std::function<std::vector<int>()> m_clipFrames;
  pipeline::LabelTable m_fileTable;  ///< labelsFromFile's, as read
  /// The map's labels with m_fileTable merged in, per sample of the map shown (empty: no file).
  pipeline::Labels m_fileLabels;
  QString m_filePath;       ///< labelsFromFile's file
  QStringList m_filePaths;  ///< the clips it was read against
  QString m_colorBy = timeChoice();
  std::vector<int> m_codes;  ///< per sample: its entry
  std::vector<Entry> m_entries;
};

}  // namespace motionmap::studio
