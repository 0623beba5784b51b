// Colour by label (View → Colour by, the Legend dock): a saved map of the 12 labelled Bandai takes
// (dataset-1_{action}_{style}_{take}.bvh, labels read from their names and saved in /labels) and a
// map computed here of four of them (labels read from the names in Studio) are drawn in the CLI's
// category colours; the legend lists each value with its frames; a click hides a value (its
// frames neither drawn nor found by hover, click, the Nearest panel or a selection) and a
// Ctrl-click shows it alone.
#include <unistd.h>

#include <QComboBox>
#include <QDir>
#include <QImage>
#include <QLabel>
#include <QListWidget>
#include <QMenu>
#include <QMenuBar>
#include <QProcess>
#include <QPushButton>
#include <QTest>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "explore/explore_panels.h"
#include "explore/legend_panel.h"
#include "explore/map_coloring.h"
#include "explore/nearest_panel.h"
#include "explore/selection_panel.h"
#include "map/map_gestures.h"
#include "map/map_view.h"
#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/pipeline/labels.h"
#include "motionmap/render/map_plot.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

namespace fs = std::filesystem;

const std::string kBandai = std::string(MOTIONMAP_SHARED_DATA) + "/bandai";

/// The twelve takes, in name order.
std::vector<std::string> bandaiPaths() {
  std::vector<std::string> paths;
  if (!fs::is_directory(kBandai)) return paths;
  for (const auto& entry : fs::directory_iterator(kBandai)) {
    if (entry.path().extension() == ".bvh") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

/// "walk" of ".../dataset-1_walk_old_001.bvh" (part 1 of the stem split at '_').
std::string actionOf(const std::string& path) {
  const std::string stem = fs::path(path).stem().string();
  const std::size_t a = stem.find('_') + 1;
  return stem.substr(a, stem.find('_', a) - a);
}

/// The colour of `pixel` of a premultiplied image, unpremultiplied.
QColor colourAt(const QImage& image, int x, int y) {
  return QColor::fromRgba(qUnpremultiply(image.pixel(x, y)));
}

bool near(const QColor& a, const QColor& b, int tolerance) {
  return std::abs(a.red() - b.red()) <= tolerance && std::abs(a.green() - b.green()) <= tolerance &&
         std::abs(a.blue() - b.blue()) <= tolerance;
}

/// Whether premultiplied pixel `pixel` is `colour` at its opacity (within `tolerance` a channel).
bool inColour(QRgb pixel, const QColor& colour, int tolerance = 1) {
  const int a = qAlpha(pixel);
  return a > 0 && std::abs(qRed(pixel) - colour.red() * a / 255) <= tolerance &&
         std::abs(qGreen(pixel) - colour.green() * a / 255) <= tolerance &&
         std::abs(qBlue(pixel) - colour.blue() * a / 255) <= tolerance;
}

/// Clicks row `row` of the legend (with `modifiers`).
void clickRow(LegendPanel* legend, int row, Qt::KeyboardModifiers modifiers = {}) {
  QListWidget* list = legend->list();
  QTest::mouseClick(list->viewport(), Qt::LeftButton, modifiers,
                    list->visualItemRect(list->item(row)).center());
}

/// The row of value `value` in the colouring's entries (−1: none).
int entryOf(const MapColoring& coloring, const QString& value) {
  for (std::size_t e = 0; e < coloring.entries().size(); ++e)
    if (coloring.entries()[e].value == value) return int(e);
  return -1;
}

/// Writes `text` to `path`.
void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

const std::string kTemplate = "{action}_{style}_{take}";

/// The entries `motionmap map --labels-from-name kTemplate --labels FILE --color-by LABEL`
/// colours by: the library's reader (pipeline::read_label_file, as the CLI reads --labels), the
/// file's labels merged into the names' (pipeline::merge_labels, as the CLI merges them),
/// sampled on the map's samples, and render::category_slots' colours.
struct CliEntry {
  std::string value;
  int count = 0;
  int category = -1;
};
std::vector<CliEntry> cliEntries(const std::string& file, const std::vector<std::string>& paths,
                                 const std::vector<int>& frames, const std::vector<int>& clipOf,
                                 const std::vector<int>& frameOf, const std::string& label) {
  pipeline::LabelTable table = pipeline::labels_from_names(paths, pipeline::NamePattern(kTemplate));
  pipeline::merge_labels(table, pipeline::read_label_file(file, paths, frames), file);
  const pipeline::Labels labels = pipeline::sample_labels(table, clipOf, frameOf);
  const pipeline::LabelColumn* column = labels.find(label);
  if (!column) return {};
  const std::vector<int> counts = column->counts();
  const std::vector<int> slot_of = render::category_slots(counts);
  std::vector<CliEntry> out;
  for (std::size_t v = 0; v < counts.size(); ++v)
    out.push_back(
        {column->categories[v].empty() ? "(none)" : column->categories[v], counts[v], slot_of[v]});
  return out;
}

/// The label columns `names` of the map CSV that `motionmap ARGS -o OUT` writes, by (clip, frame):
/// the CLI run in a child process. Empty (with a failure) when it fails.
std::map<std::pair<int, int>, std::vector<std::string>> cliLabels(
    const QStringList& args, const fs::path& out, const std::vector<std::string>& names) {
  std::map<std::pair<int, int>, std::vector<std::string>> rows;
#ifdef MOTIONMAP_CLI_EXE
  QProcess cli;
  cli.start(MOTIONMAP_CLI_EXE,
            args + QStringList{"-q", "-o", QString::fromStdString(out.string())});
  EXPECT_TRUE(cli.waitForFinished(testing::kTimeoutMs));
  EXPECT_EQ(cli.exitCode(), 0) << cli.readAllStandardError().toStdString();
  std::ifstream in(out);
  std::string line;
  std::vector<std::size_t> column;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::size_t start = 0;
    for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
      cells.push_back(line.substr(start, comma - start));
    cells.push_back(line.substr(start));
    if (column.empty()) {  // the header: clip, frame, coordinates, labels
      for (const std::string& name : names) {
        const auto it = std::find(cells.begin(), cells.end(), name);
        EXPECT_NE(it, cells.end()) << "no column " << name << " in " << line;
        if (it == cells.end()) return {};
        column.push_back(std::size_t(it - cells.begin()));
      }
      EXPECT_EQ(cells[0], "clip");
      EXPECT_EQ(cells[1], "frame");
      continue;
    }
    std::vector<std::string>& values = rows[{std::stoi(cells[0]), std::stoi(cells[1])}];
    for (const std::size_t c : column) values.push_back(cells.at(c));
  }
#else
  (void)args, (void)out, (void)names;
  ADD_FAILURE() << "the CLI (motionmap) was not built with these tests";
#endif
  return rows;
}

/// Expects the colouring's values of each label of `names` on every sample (clipOf, frameOf) to
/// be the CLI's `cli` values of the same clip and frame; returns the samples compared.
int expectCliValues(const MapColoring& coloring, const std::vector<std::string>& names,
                    const std::vector<int>& clipOf, const std::vector<int>& frameOf,
                    const std::map<std::pair<int, int>, std::vector<std::string>>& cli) {
  EXPECT_EQ(cli.size(), clipOf.size());
  int compared = 0;
  for (std::size_t l = 0; l < names.size(); ++l) {
    const pipeline::LabelColumn* column = coloring.column(names[l]);
    EXPECT_NE(column, nullptr) << names[l];
    if (!column) return 0;
    int mismatches = 0;
    for (std::size_t r = 0; r < clipOf.size(); ++r) {
      const auto it = cli.find({clipOf[r], frameOf[r]});
      EXPECT_NE(it, cli.end()) << "clip " << clipOf[r] << " frame " << frameOf[r];
      if (it == cli.end()) return 0;
      if (column->value(int(r)) != it->second[l] && ++mismatches <= 5)
        ADD_FAILURE() << names[l] << " of clip " << clipOf[r] << " frame " << frameOf[r] << ": '"
                      << column->value(int(r)) << "', the CLI '" << it->second[l] << "'";
      compared += l == 0;
    }
    EXPECT_EQ(mismatches, 0) << names[l];
  }
  return compared;
}

/// Expects the colouring's entries to be `want`, value by value.
void expectEntries(const MapColoring& coloring, const std::vector<CliEntry>& want) {
  const auto& entries = coloring.entries();
  ASSERT_EQ(entries.size(), want.size());
  for (std::size_t e = 0; e < want.size(); ++e) {
    EXPECT_EQ(entries[e].value.toStdString(), want[e].value);
    EXPECT_EQ(entries[e].count, want[e].count) << want[e].value;
    EXPECT_EQ(entries[e].category, want[e].category) << want[e].value;
    EXPECT_EQ(entries[e].color(), render::category_color(want[e].category)) << want[e].value;
  }
}

// The twelve takes' PCA map saved with their labels (action, style, take) as lib.mmap.h5.
class LabelledLibrary : public ::testing::Test {
 protected:
  void SetUp() override {
    m_paths = bandaiPaths();
    if (m_paths.size() != 12) GTEST_SKIP() << "the 12 Bandai takes are not in " << kBandai;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = fs::temp_directory_path() /
            ("motionmap-studio-labels-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
    std::vector<Clip> clips;
    for (const std::string& path : m_paths) clips.push_back(io::load_clip(path));
    pipeline::ClipMapOptions options;
    options.embed.method = embed::Method::Pca;
    const pipeline::ClipMap map = pipeline::map_clips(clips, options);
    mapfile::MapFile file = mapfile::make_map_file(clips, map, options);
    file.labels = pipeline::sample_labels(
        pipeline::labels_from_names(m_paths, pipeline::NamePattern("{action}_{style}_{take}")),
        map.features->clip_of, map.features->frame_of);
    m_file = (m_dir / "lib.mmap.h5").string();
    mapfile::write_map_file(m_file, file);
    m_window = std::make_unique<MainWindow>();
    m_window->setInteractive(false);
    m_window->resize(1280, 720);
    m_window->show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(m_window.get()));
    ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)))
        << m_window->lastError().toStdString();
    m_coloring = m_window->explore()->coloring();
    m_legend = m_window->explore()->legend();
  }
  void TearDown() override {
    m_window.reset();
    if (!m_dir.empty()) fs::remove_all(m_dir);
  }

  const mapfile::MapFile& file() const { return m_window->savedMap()->file(); }
  /// The action of map row `row`, from its clip's file name.
  std::string actionOfRow(int row) const {
    return actionOf(m_paths[std::size_t(file().clip_of[std::size_t(row)])]);
  }
  QPointF pixelOf(int row) const {
    const auto& xy = file().coordinates;
    return m_window->mapView()->toWidget(Eigen::Vector2d(xy(row, 0), xy(row, 1)));
  }

  fs::path m_dir;
  std::string m_file;
  std::vector<std::string> m_paths;
  std::unique_ptr<MainWindow> m_window;
  MapColoring* m_coloring = nullptr;
  LegendPanel* m_legend = nullptr;
};

TEST_F(LabelledLibrary, OffersTimeClipAndTheMapsLabels) {
  EXPECT_EQ(m_coloring->choices(), QStringList({"time", "clip", "action", "style", "take"}));
  EXPECT_EQ(m_coloring->colorBy(), "time");
  EXPECT_TRUE(m_coloring->entries().empty());
  EXPECT_FALSE(m_window->mapView()->categoriesShown());
  EXPECT_FALSE(m_legend->isVisible());  // until a label colours the map
}

TEST_F(LabelledLibrary, LegendCountsAreTheFramesOfEachActionInThePalettesColours) {
  ASSERT_TRUE(m_coloring->setColorBy("action"));
  EXPECT_TRUE(m_legend->isVisible());
  EXPECT_EQ(m_legend->choice()->currentText(), "action");
  // The frames of each action, counted from the clips' names.
  std::map<std::string, int> frames;
  for (int r = 0; r < file().num_samples(); ++r) ++frames[actionOfRow(r)];
  ASSERT_EQ(frames.size(), 5u);  // bow, dash, punch, run, walk
  const auto& entries = m_coloring->entries();
  ASSERT_EQ(entries.size(), frames.size());
  ASSERT_EQ(m_legend->list()->count(), int(frames.size()));
  int e = 0;
  for (const auto& [action, count] : frames) {  // value order
    EXPECT_EQ(entries[std::size_t(e)].value.toStdString(), action);
    EXPECT_EQ(entries[std::size_t(e)].count, count) << action;
    EXPECT_EQ(m_legend->list()->item(e)->text(),
              QString("%1 (%2)").arg(QString::fromStdString(action)).arg(count));
    // Five values: each in its own colour of the CLI's palette, in value order.
    EXPECT_EQ(entries[std::size_t(e)].color(), render::category_color(e));
    ++e;
  }
  EXPECT_EQ(m_legend->summary()->text(),
            QString("%1 of %1 frames shown").arg(file().num_samples()));
  // Each sample's category is its action's.
  const std::vector<int>& categories = m_window->mapView()->sampleCategories();
  ASSERT_EQ(int(categories.size()), file().num_samples());
  for (int r = 0; r < file().num_samples(); ++r) {
    const int expected = int(std::distance(frames.begin(), frames.find(actionOfRow(r))));
    ASSERT_EQ(categories[std::size_t(r)], expected) << "row " << r;
  }
  // The density image: every action's colour is drawn (in the pixels its frames alone fill).
  const QImage image = m_window->mapView()->densityImage();
  for (int c = 0; c < 5; ++c) {
    int close = 0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x)
        close += inColour(image.pixel(x, y), render::category_color(c));
    EXPECT_GT(close, 0) << "no pixel in the colour of "
                        << entries[std::size_t(c)].value.toStdString();
  }
}

TEST_F(LabelledLibrary, AHiddenActionIsNeitherDrawnNorPicked) {
  ASSERT_TRUE(m_coloring->setColorBy("action"));
  const int walk = entryOf(*m_coloring, "walk");
  ASSERT_GE(walk, 0);
  const int walkFrames = m_coloring->entries()[std::size_t(walk)].count;
  clickRow(m_legend, walk);  // a plain click hides it
  ASSERT_FALSE(m_coloring->entries()[std::size_t(walk)].shown);
  MapView* view = m_window->mapView();
  EXPECT_TRUE(view->hidesSamples());
  EXPECT_EQ(m_coloring->shownSamples(), file().num_samples() - walkFrames);
  EXPECT_EQ(m_legend->summary()->text(), QString("%1 of %2 frames shown")
                                             .arg(file().num_samples() - walkFrames)
                                             .arg(file().num_samples()));
  EXPECT_TRUE(m_legend->list()->item(walk)->font().strikeOut());
  // Not drawn: no pixel of the density image in walk's colour.
  const QImage image = view->densityImage();
  const QColor walkColour = m_coloring->entries()[std::size_t(walk)].color();
  int painted = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (qAlpha(image.pixel(x, y)) > 0) {
        ++painted;
        ASSERT_FALSE(inColour(image.pixel(x, y), walkColour)) << x << "," << y;
      }
  EXPECT_GT(painted, 100);
  // Not picked by hover (and so not by a click), nor by the nearest frames, nor by a selection.
  auto* gestures = m_window->findChild<MapGestures*>();
  ASSERT_NE(gestures, nullptr);
  auto* nearest = m_window->findChild<NearestPanel*>();
  ASSERT_NE(nearest, nullptr);
  int walkRows = 0, found = 0;
  for (int r = 0; r < file().num_samples(); r += 7) {
    if (actionOfRow(r) != "walk") continue;
    ++walkRows;
    const QPointF pixel = pixelOf(r);
    const int hit = gestures->sampleNear(view->toMap(pixel), pixel);
    if (hit >= 0) {
      ++found;
      EXPECT_NE(actionOfRow(hit), "walk") << "row " << r << " picked hidden row " << hit;
    }
    if (r % 70 == 0) {
      nearest->showAround(view->toMap(pixel));
      for (const NearestPanel::Entry& n : nearest->entries())
        EXPECT_NE(actionOf(m_paths[std::size_t(n.clip)]), "walk");
    }
  }
  EXPECT_GT(walkRows, 50);
  // Hovering over a walk frame names no walk clip.
  for (int r = 0; r < file().num_samples(); r += 97) {
    if (actionOfRow(r) != "walk") continue;
    QTest::mouseMove(view, pixelOf(r).toPoint());
    EXPECT_FALSE(view->hoverText().contains("_walk_")) << view->hoverText().toStdString();
  }
  auto* selection = m_window->findChild<SelectionPanel*>();
  ASSERT_NE(selection, nullptr);
  const QRectF all = view->viewExtent().adjusted(-1, -1, 1, 1);
  selection->select(QPolygonF(all));
  EXPECT_EQ(int(selection->frames().size()), file().num_samples() - walkFrames);
  for (const SelectedFrame& f : selection->frames())
    ASSERT_NE(actionOf(m_paths[std::size_t(f.clip)]), "walk");
  // Shown again: picked again.
  clickRow(m_legend, walk);
  EXPECT_TRUE(m_coloring->entries()[std::size_t(walk)].shown);
  EXPECT_FALSE(view->hidesSamples());
  int row = -1;
  for (int r = 0; r < file().num_samples() && row < 0; ++r)
    if (actionOfRow(r) == "walk") row = r;
  const int hit = gestures->sampleNear(view->toMap(pixelOf(row)), pixelOf(row));
  ASSERT_GE(hit, 0);
}

TEST_F(LabelledLibrary, ALegendClickComposesThePictureAFullRedrawDraws) {
  // A click recolours the density under the trajectory layer kept from before (not stroked
  // again): the picture is the one a redraw of everything gives.
  ASSERT_TRUE(m_coloring->setColorBy("action"));
  MapView* view = m_window->mapView();
  const QImage before = view->grab().toImage();
  clickRow(m_legend, entryOf(*m_coloring, "walk"));
  const QImage hidden = view->grab().toImage();
  EXPECT_NE(hidden, before);
  view->setHighlight(Eigen::MatrixXd(0, 2));  // the whole picture drawn again
  EXPECT_EQ(view->grab().toImage(), hidden);
  clickRow(m_legend, entryOf(*m_coloring, "walk"));
  EXPECT_EQ(view->grab().toImage(), before);
}

TEST_F(LabelledLibrary, CtrlClickSolosAValueAndAgainShowsAll) {
  ASSERT_TRUE(m_coloring->setColorBy("style"));
  const int old = entryOf(*m_coloring, "old");
  ASSERT_GE(old, 0);
  clickRow(m_legend, old, Qt::ControlModifier);
  const auto& entries = m_coloring->entries();
  for (std::size_t e = 0; e < entries.size(); ++e) EXPECT_EQ(entries[e].shown, int(e) == old);
  EXPECT_EQ(m_coloring->shownSamples(), entries[std::size_t(old)].count);
  const std::vector<int>& categories = m_window->mapView()->sampleCategories();
  int shown = 0;
  for (const int c : categories) shown += c != MapView::kHiddenCategory;
  EXPECT_EQ(shown, entries[std::size_t(old)].count);
  // Every pixel drawn is old's colour.
  const QImage image = m_window->mapView()->densityImage();
  int painted = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (qAlpha(image.pixel(x, y)) > 0) {
        ++painted;
        ASSERT_TRUE(inColour(image.pixel(x, y), entries[std::size_t(old)].color()))
            << x << "," << y;
      }
  EXPECT_GT(painted, 50);
  EXPECT_TRUE(m_legend->showAllButton()->isEnabled());
  clickRow(m_legend, old, Qt::ControlModifier);  // again: every value
  for (const auto& e : m_coloring->entries()) EXPECT_TRUE(e.shown);
  EXPECT_FALSE(m_legend->showAllButton()->isEnabled());
  // Solo from the menu's action, then Show all.
  m_coloring->solo(0);
  EXPECT_EQ(m_coloring->shownSamples(), m_coloring->entries()[0].count);
  QTest::mouseClick(m_legend->showAllButton(), Qt::LeftButton);
  EXPECT_EQ(m_coloring->shownSamples(), file().num_samples());
}

TEST_F(LabelledLibrary, TheViewMenuAndTheLegendsChoiceColourTheMap) {
  // View → Colour by: time, clip and the map's labels, the one in use checked.
  QMenu* colourBy = nullptr;
  for (QMenu* menu : m_window->menuBar()->findChildren<QMenu*>())
    if (menu->title() == "Colour &by") colourBy = menu;
  ASSERT_NE(colourBy, nullptr);
  emit colourBy->aboutToShow();
  QStringList entries;
  QAction* style = nullptr;
  for (QAction* a : colourBy->actions()) {
    if (a->isSeparator()) continue;
    entries << a->text();
    if (a->text() == "style") style = a;
    if (a->text() == "Time") {
      EXPECT_TRUE(a->isChecked());
    }
  }
  EXPECT_EQ(entries, QStringList({"Time", "Clip", "action", "style", "take",
                                  "Labels from file names…", "Labels from file…"}));
  ASSERT_NE(style, nullptr);
  style->trigger();
  EXPECT_EQ(m_coloring->colorBy(), "style");
  EXPECT_EQ(m_coloring->entries().size(), 6u);  // normal, old, angry, feminine, proud, tired
  EXPECT_TRUE(m_legend->isVisible());
  EXPECT_EQ(m_legend->choice()->currentText(), "style");
  // The legend's choice: back to time, the map's own colours.
  const int time = m_legend->choice()->findText("time");
  ASSERT_GE(time, 0);
  emit m_legend->choice()->textActivated("time");
  EXPECT_EQ(m_coloring->colorBy(), "time");
  EXPECT_FALSE(m_window->mapView()->categoriesShown());
  EXPECT_EQ(m_legend->list()->count(), 0);
  // Another map file without labels: time and clip only, the colouring back to time.
  ASSERT_TRUE(m_coloring->setColorBy("action"));
  ASSERT_TRUE(m_window->openFile(QString::fromStdString(m_paths[0])));
  EXPECT_EQ(m_coloring->colorBy(), "time");
  EXPECT_EQ(m_coloring->choices(), QStringList({"time"}));
}

TEST_F(LabelledLibrary, UnknownLabelsAndNamePatternsOnASavedMapAreRefused) {
  EXPECT_FALSE(m_coloring->setColorBy("mood"));
  EXPECT_TRUE(m_window->lastError().contains("'mood'")) << m_window->lastError().toStdString();
  EXPECT_TRUE(m_window->lastError().contains("action"));
  EXPECT_EQ(m_coloring->colorBy(), "time");
  EXPECT_FALSE(m_coloring->labelsFromNames("{action}_{style}_{take}"));
  EXPECT_TRUE(m_window->lastError().contains("saved map has its own labels"));
}

TEST_F(LabelledLibrary, ClipColoursListEveryClipWithItsFramesAndGreyBeyondThePalette) {
  ASSERT_TRUE(m_coloring->setColorBy("clip"));
  const auto& entries = m_coloring->entries();
  ASSERT_EQ(entries.size(), 12u);
  // Twelve clips: as many colours as the palette has, none grey.
  std::set<int> categories;
  for (std::size_t c = 0; c < entries.size(); ++c) {
    EXPECT_EQ(entries[c].value.toStdString(), fs::path(m_paths[c]).filename().string());
    EXPECT_EQ(entries[c].count, file().clips[c].samples);
    categories.insert(entries[c].category);
  }
  EXPECT_EQ(categories.size(), 12u);
  EXPECT_EQ(*categories.begin(), 0);
}

TEST_F(LabelledLibrary, ThePictureShowsTheColoursAndTheLegend) {
  ASSERT_TRUE(m_coloring->setColorBy("action"));
  clickRow(m_legend, entryOf(*m_coloring, "bow"));
  QTest::qWait(50);
  const QImage picture = m_window->grab().toImage();
  ASSERT_FALSE(picture.isNull());
  const QString path = QDir::current().filePath("studio-labels.png");
  EXPECT_TRUE(picture.save(path)) << path.toStdString();
  // The legend lies inside the window, beside the map.
  const QRect legend(m_legend->mapTo(m_window.get(), QPoint(0, 0)), m_legend->size());
  EXPECT_TRUE(m_window->rect().contains(legend));
  EXPECT_FALSE(legend.intersects(QRect(m_window->mapView()->mapTo(m_window.get(), QPoint(0, 0)),
                                       m_window->mapView()->size())));
}

TEST_F(LabelledLibrary, ALabelFileColoursASavedMapAsTheCliReadsIt) {
  // One row per clip, named by file name or by stem: a "speed" label, and "style" again (the
  // file's values replace the map's where it gives them: the last clip keeps its name's),
  // leaving one clip without a speed ("(none)").
  std::string csv = "# speed of each take\nclip,speed,style\n";
  for (std::size_t c = 0; c + 1 < m_paths.size(); ++c) {
    const fs::path p(m_paths[c]);
    const std::string action = actionOf(m_paths[c]);
    csv += (c % 2 ? p.filename().string() : p.stem().string()) + "," +
           (action == "run" || action == "dash" ? "fast" : "slow") + ",s" + std::to_string(c % 3) +
           "\n";
  }
  const fs::path labels = m_dir / "speed.csv";
  writeText(labels, csv);
  ASSERT_TRUE(m_coloring->labelsFromFile(QString::fromStdString(labels.string())))
      << m_window->lastError().toStdString();
  EXPECT_EQ(m_coloring->labelFile().toStdString(), labels.string());
  EXPECT_EQ(m_coloring->choices(),
            QStringList({"time", "clip", "action", "style", "take", "speed"}));
  EXPECT_EQ(m_coloring->colorBy(), "speed");  // the file's first label
  EXPECT_TRUE(m_legend->isVisible());
  std::vector<int> frames;
  for (const auto& clip : file().clips) frames.push_back(clip.frames);
  const auto want = [&](const std::string& label) {
    return cliEntries(labels.string(), m_paths, frames, file().clip_of, file().frame_of, label);
  };
  expectEntries(*m_coloring, want("speed"));
  ASSERT_EQ(m_coloring->entries().size(), 3u);  // (none), fast, slow
  EXPECT_EQ(m_coloring->entries()[0].value, "(none)");
  EXPECT_EQ(m_coloring->entries()[0].count, file().clips.back().samples);
  // Each sample's category is its value's.
  const std::vector<int>& categories = m_window->mapView()->sampleCategories();
  ASSERT_EQ(int(categories.size()), file().num_samples());
  const auto& speed = want("speed");
  const pipeline::Labels sampled = pipeline::sample_labels(
      pipeline::read_label_file(labels.string(), m_paths, frames), file().clip_of, file().frame_of);
  const pipeline::LabelColumn* column = sampled.find("speed");
  ASSERT_NE(column, nullptr);
  for (int r = 0; r < file().num_samples(); ++r)
    ASSERT_EQ(categories[std::size_t(r)],
              speed[std::size_t(column->codes[std::size_t(r)])].category)
        << "row " << r;
  // The file's "style" merged into the map's: its values s0, s1, s2 and the last clip's "tired".
  ASSERT_TRUE(m_coloring->setColorBy("style"));
  expectEntries(*m_coloring, want("style"));
  ASSERT_EQ(m_coloring->entries().size(), 4u);
  EXPECT_EQ(m_coloring->entries()[3].value, "tired");
  EXPECT_EQ(m_coloring->entries()[3].count, file().clips.back().samples);
  // The map's own labels still colour it.
  ASSERT_TRUE(m_coloring->setColorBy("action"));
  EXPECT_EQ(m_coloring->entries().size(), 5u);
  // The Legend's button and the menu's entry ask for a file (here, the dialog is not shown).
  EXPECT_TRUE(m_legend->labelFileButton()->isVisible());
}

TEST_F(LabelledLibrary, ALabelFileMergesIntoTheMapsLabelsSpanBySpanAsTheCliDoes) {
  // Spans of some frames of three takes: a label the map has from the names ("action") and a
  // new one ("mood"). The file's values where its spans cover frames, the names' elsewhere: the
  // values of `motionmap map TAKES --labels-from-name … --labels FILE`'s label columns.
  const fs::path labels = m_dir / "spans.csv";
  writeText(labels,
            "clip,start,end,action,mood\n"
            "dataset-1_walk_old_001.bvh,10,59,limp,calm\n"
            "dataset-1_run_angry_001,0,29,sprint,tense\n"
            "dataset-1_bow_normal_001,40,137,bow_deep,calm\n"
            "dataset-1_walk_old_001,30,39,stumble,tense\n");
  ASSERT_TRUE(m_coloring->labelsFromFile(QString::fromStdString(labels.string())))
      << m_window->lastError().toStdString();
  EXPECT_EQ(m_coloring->choices(),
            QStringList({"time", "clip", "action", "style", "take", "mood"}));
  EXPECT_EQ(m_coloring->colorBy(), "action");  // the file's first label
  // Every value of "action": the names' five and the file's three.
  QStringList values;
  for (const auto& e : m_coloring->entries()) values << e.value;
  EXPECT_EQ(values, QStringList({"bow", "bow_deep", "dash", "limp", "punch", "run", "sprint",
                                 "stumble", "walk"}));
  QStringList args{"map"};
  for (const std::string& p : m_paths) args << QString::fromStdString(p);
  args << "-m"
       << "pca"
       << "--labels-from-name" << QString::fromStdString(kTemplate) << "--labels"
       << QString::fromStdString(labels.string());
  const std::vector<std::string> names = {"action", "style", "take", "mood"};
  const auto cli = cliLabels(args, m_dir / "cli.csv", names);
  EXPECT_EQ(expectCliValues(*m_coloring, names, file().clip_of, file().frame_of, cli),
            file().num_samples());
  // Frames outside the spans keep the names' action: some walk_old frames are still "walk".
  const pipeline::LabelColumn* action = m_coloring->column("action");
  ASSERT_NE(action, nullptr);
  const int walkOld = int(
      std::find_if(m_paths.begin(), m_paths.end(),
                   [](const std::string& p) { return p.find("walk_old") != std::string::npos; }) -
      m_paths.begin());
  std::set<std::string> walkOldActions;
  for (int r = 0; r < file().num_samples(); ++r)
    if (file().clip_of[std::size_t(r)] == walkOld) walkOldActions.insert(action->value(r));
  EXPECT_EQ(walkOldActions, (std::set<std::string>{"limp", "stumble", "walk"}));
  // The colours are the CLI's for the merged labels.
  std::vector<int> frames;
  for (const auto& clip : file().clips) frames.push_back(clip.frames);
  expectEntries(*m_coloring, cliEntries(labels.string(), m_paths, frames, file().clip_of,
                                        file().frame_of, "action"));
}

TEST_F(LabelledLibrary, SpansOfFramesGiveTheClisColoursAndGreyBeyondTheTwelve) {
  // Two halves of each take, each its own value: 24 values, the 11 most frequent coloured and
  // the others grey, as `motionmap map --labels … --color-by half` colours them.
  std::string csv = "clip,start,end,half\n";
  for (std::size_t c = 0; c < m_paths.size(); ++c) {
    const int frames = file().clips[c].frames;
    const std::string name = fs::path(m_paths[c]).filename().string();
    csv += name + ",0," + std::to_string(frames / 2 - 1) + ",c" + std::to_string(c) + "a\n";
    csv += "\"" + name + "\"," + std::to_string(frames / 2) + "," + std::to_string(frames - 1) +
           ",c" + std::to_string(c) + "b\n";
  }
  const fs::path labels = m_dir / "halves.csv";
  writeText(labels, csv);
  ASSERT_TRUE(m_coloring->labelsFromFile(QString::fromStdString(labels.string())))
      << m_window->lastError().toStdString();
  EXPECT_EQ(m_coloring->colorBy(), "half");
  std::vector<int> frames;
  for (const auto& clip : file().clips) frames.push_back(clip.frames);
  const std::vector<CliEntry> want =
      cliEntries(labels.string(), m_paths, frames, file().clip_of, file().frame_of, "half");
  ASSERT_EQ(want.size(), 24u);
  expectEntries(*m_coloring, want);
  int grey = 0;
  for (const auto& e : m_coloring->entries()) grey += e.category < 0;
  EXPECT_EQ(grey, 24 - (render::kCategoryColors - 1));
  EXPECT_EQ(m_legend->list()->count(), 24);
  // The same clips in another map file: the file's labels stay; a map of other clips drops them.
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  EXPECT_EQ(m_coloring->colorBy(), "half");
  expectEntries(*m_coloring, want);
  ASSERT_TRUE(m_window->openFile(QString::fromStdString(m_paths[0])));
  EXPECT_EQ(m_coloring->colorBy(), "time");
  EXPECT_TRUE(m_coloring->labelFile().isEmpty());
}

TEST_F(LabelledLibrary, ABadLabelFileIsAMessageNamingTheFileAndLine) {
  ASSERT_TRUE(m_coloring->setColorBy("action"));
  const auto refused = [&](const std::string& name, const std::string& text,
                           const std::string& line, const std::string& what) {
    const fs::path path = m_dir / name;
    writeText(path, text);
    EXPECT_FALSE(m_coloring->labelsFromFile(QString::fromStdString(path.string())));
    const std::string error = m_window->lastError().toStdString();
    EXPECT_NE(error.find(path.string() + ":" + line + ":"), std::string::npos) << error;
    EXPECT_NE(error.find(what), std::string::npos) << error;
    // Nothing changed: the colouring before stays.
    EXPECT_EQ(m_coloring->colorBy(), "action");
    EXPECT_EQ(m_coloring->entries().size(), 5u);
    EXPECT_TRUE(m_coloring->labelFile().isEmpty());
  };
  const std::string first = fs::path(m_paths[0]).filename().string();
  refused("unknown.csv", "clip,speed\n" + first + ",slow\nnot_a_take.bvh,fast\n", "3",
          "not_a_take");
  refused("fields.csv", "clip,speed\n" + first + ",slow,extra\n", "2", "");
  refused("beyond.csv", "clip,start,end,half\n" + first + ",0,99999,a\n", "2", "");
  refused("bad.json", "[{\"clip\": \"" + first + "\", \"speed\": }]", "1", "");
  // A file that cannot be read: its path in the message.
  EXPECT_FALSE(m_coloring->labelsFromFile(QString::fromStdString((m_dir / "none.csv").string())));
  EXPECT_NE(m_window->lastError().toStdString().find("none.csv"), std::string::npos)
      << m_window->lastError().toStdString();
  EXPECT_EQ(m_coloring->colorBy(), "action");
}

// A map computed here of four takes, labelled from their names in Studio.
TEST(StudioLabels, AComputedMapColoursByLabelsReadFromTheClipsNames) {
  const std::vector<std::string> all = bandaiPaths();
  if (all.size() != 12) GTEST_SKIP() << "the 12 Bandai takes are not in " << kBandai;
  std::vector<std::string> paths;
  for (const std::string& p : all)
    if (p.find("run_angry") != std::string::npos || p.find("run_old") != std::string::npos ||
        p.find("walk_angry") != std::string::npos || p.find("walk_old") != std::string::npos)
      paths.push_back(p);
  ASSERT_EQ(paths.size(), 4u);
  MainWindow w;
  w.setInteractive(false);
  w.resize(1000, 600);
  w.show();
  w.setMethod(embed::Method::Pca);
  ASSERT_TRUE(w.openFile(QString::fromStdString(paths[0])));
  for (std::size_t i = 1; i < paths.size(); ++i)
    ASSERT_TRUE(w.addFile(QString::fromStdString(paths[i]))) << w.lastError().toStdString();
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return w.currentMap() != nullptr && !w.isComputing() && w.clipCount() == 4; },
      testing::kTimeoutMs));
  MapColoring* coloring = w.explore()->coloring();
  EXPECT_EQ(coloring->choices(), QStringList({"time", "clip"}));
  // A bad pattern: the library's message.
  EXPECT_FALSE(coloring->labelsFromNames("{action"));
  EXPECT_FALSE(w.lastError().isEmpty());
  ASSERT_TRUE(coloring->labelsFromNames("{action}_{style}_{take}")) << w.lastError().toStdString();
  EXPECT_EQ(coloring->choices(), QStringList({"time", "clip", "action", "style", "take"}));
  EXPECT_EQ(coloring->colorBy(), "action");
  const MapResult& map = *w.currentMap();
  const auto& clipOf = map.map.features->clip_of;
  const auto actionOfRow = [&](int r) {
    return actionOf(paths[std::size_t(clipOf[std::size_t(r)])]);
  };
  ASSERT_EQ(coloring->entries().size(), 2u);  // run, walk
  const int run = entryOf(*coloring, "run"), walk = entryOf(*coloring, "walk");
  int runFrames = 0;
  for (std::size_t r = 0; r < clipOf.size(); ++r) runFrames += actionOfRow(int(r)) == "run";
  EXPECT_EQ(coloring->entries()[std::size_t(run)].count, runFrames);
  // Walk alone: its samples' pixels in walk's colour, none in run's.
  coloring->solo(walk);
  MapView* view = w.mapView();
  const QImage image = view->grab().toImage();
  const QColor walkColour = render::category_color(coloring->entries()[std::size_t(walk)].category);
  const QColor runColour = render::category_color(coloring->entries()[std::size_t(run)].category);
  const auto& xy = map.map.embedding.coordinates;
  int walkRows = 0, walkColoured = 0;
  const qreal dpr = image.devicePixelRatio();
  for (Eigen::Index r = 0; r < xy.rows(); ++r) {
    const QPointF p = view->toWidget(Eigen::Vector2d(xy(r, 0), xy(r, 1))) * dpr;
    const QColor c = image.pixelColor(p.toPoint());
    EXPECT_FALSE(near(c, runColour, 20)) << "row " << r;
    if (actionOfRow(int(r)) == "walk") {
      ++walkRows;
      walkColoured += near(c, walkColour, 40);
    }
  }
  EXPECT_GT(walkColoured, walkRows * 8 / 10) << walkColoured << " of " << walkRows;
  coloring->showAll();
  EXPECT_TRUE(w.grab().toImage().save(QDir::current().filePath("studio-labels-computed.png")));
  coloring->solo(walk);
  // Run hidden: hovering over its frames finds none of them.
  auto* gestures = w.findChild<MapGestures*>();
  for (Eigen::Index r = 0; r < xy.rows(); r += 5) {
    if (actionOfRow(int(r)) != "run") continue;
    const QPointF pixel = view->toWidget(Eigen::Vector2d(xy(r, 0), xy(r, 1)));
    const int hit = gestures->sampleNear(view->toMap(pixel), pixel);
    if (hit >= 0) {
      EXPECT_EQ(actionOfRow(hit), "walk");
    }
  }
  // A label file on a map computed here: read as the CLI reads it (spans of frames).
  {
    const fs::path dir = fs::temp_directory_path() /
                         ("motionmap-studio-labels-computed-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::string csv = "clip,start,end,phase\n";
    std::vector<int> frames;
    for (const std::string& p : paths) {
      const int n = io::load_clip(p).motion.num_frames;
      frames.push_back(n);
      csv += fs::path(p).stem().string() + ",0," + std::to_string(n / 3) + ",early\n";
    }
    writeText(dir / "phase.csv", csv);
    ASSERT_TRUE(coloring->labelsFromFile(QString::fromStdString((dir / "phase.csv").string())))
        << w.lastError().toStdString();
    EXPECT_EQ(coloring->choices(),
              QStringList({"time", "clip", "action", "style", "take", "phase"}));
    expectEntries(*coloring, cliEntries((dir / "phase.csv").string(), paths, frames, clipOf,
                                        map.map.features->frame_of, "phase"));
    ASSERT_EQ(coloring->entries().size(), 2u);  // (none), early
    fs::remove_all(dir);
    ASSERT_TRUE(coloring->setColorBy("action"));
    coloring->solo(walk);
  }
  // Another method: the labels and the solo stay with the same clips.
  w.setMethod(embed::Method::Isomap);
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return w.currentMap() && w.currentMap()->options.embed.method == embed::Method::Isomap;
      },
      testing::kTimeoutMs));
  EXPECT_EQ(coloring->colorBy(), "action");
  EXPECT_FALSE(coloring->entries()[std::size_t(run)].shown);
  EXPECT_TRUE(view->hidesSamples());
  EXPECT_TRUE(coloring->choices().contains("phase"));
}

// A map computed here, labelled from the names in Studio, then from a file of one row per clip for
// some clips: the names' labels with the file's values where it gives them, as the CLI merges.
TEST(StudioLabels, OnAComputedMapAFilesLabelsMergeIntoTheNamesAsTheCliDoes) {
  const std::vector<std::string> all = bandaiPaths();
  if (all.size() != 12) GTEST_SKIP() << "the 12 Bandai takes are not in " << kBandai;
  std::vector<std::string> paths;
  for (const std::string& p : all)
    if (p.find("run_angry") != std::string::npos || p.find("run_old") != std::string::npos ||
        p.find("walk_angry") != std::string::npos || p.find("walk_old") != std::string::npos)
      paths.push_back(p);
  ASSERT_EQ(paths.size(), 4u);
  MainWindow w;
  w.setInteractive(false);
  w.resize(1000, 600);
  w.show();
  w.setMethod(embed::Method::Pca);
  ASSERT_TRUE(w.openFile(QString::fromStdString(paths[0])));
  for (std::size_t i = 1; i < paths.size(); ++i)
    ASSERT_TRUE(w.addFile(QString::fromStdString(paths[i]))) << w.lastError().toStdString();
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return w.currentMap() != nullptr && !w.isComputing() && w.clipCount() == 4; },
      testing::kTimeoutMs));
  MapColoring* coloring = w.explore()->coloring();
  const fs::path dir =
      fs::temp_directory_path() / ("motionmap-studio-labels-merge-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // The file first, the names after: the file's values still win where it gives them.
  writeText(dir / "styles.csv",
            "clip,style,speed\ndataset-1_run_old_001,brisk,fast\ndataset-1_walk_angry_001.bvh,"
            "stomp,slow\n");
  ASSERT_TRUE(coloring->labelsFromFile(QString::fromStdString((dir / "styles.csv").string())))
      << w.lastError().toStdString();
  EXPECT_EQ(coloring->choices(), QStringList({"time", "clip", "style", "speed"}));
  ASSERT_TRUE(coloring->labelsFromNames(QString::fromStdString(kTemplate)))
      << w.lastError().toStdString();
  EXPECT_EQ(coloring->choices(), QStringList({"time", "clip", "action", "style", "take", "speed"}));
  ASSERT_TRUE(coloring->setColorBy("style"));
  QStringList values;
  for (const auto& e : coloring->entries()) values << e.value;
  EXPECT_EQ(values, QStringList({"angry", "brisk", "old", "stomp"}));
  QStringList args{"map"};
  for (const std::string& p : paths) args << QString::fromStdString(p);
  args << "-m"
       << "pca"
       << "--labels-from-name" << QString::fromStdString(kTemplate) << "--labels"
       << QString::fromStdString((dir / "styles.csv").string());
  const std::vector<std::string> names = {"action", "style", "take", "speed"};
  const auto cli = cliLabels(args, dir / "cli.csv", names);
  const MapResult& map = *w.currentMap();
  EXPECT_EQ(
      expectCliValues(*coloring, names, map.map.features->clip_of, map.map.features->frame_of, cli),
      int(map.map.features->clip_of.size()));
  // Another method: the merged labels stay.
  w.setMethod(embed::Method::Svd);
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return w.currentMap() && w.currentMap()->options.embed.method == embed::Method::Svd &&
               !w.isComputing();
      },
      testing::kTimeoutMs));
  const MapResult& svd = *w.currentMap();
  EXPECT_EQ(
      expectCliValues(*coloring, names, svd.map.features->clip_of, svd.map.features->frame_of, cli),
      int(svd.map.features->clip_of.size()));
  fs::remove_all(dir);
}

TEST(StudioLabels, TheCategoryDensityMixesColoursAndLeavesHiddenPointsOut) {
  Eigen::MatrixXd points(4, 2);
  points << 0.5, 0.5, 0.5, 0.5, 1.5, 0.5, 1.5, 0.5;
  const QImage image = render::category_density_image(points, {0, 1, 2, MapView::kHiddenCategory},
                                                      QTransform(), QSize(2, 1));
  ASSERT_EQ(image.size(), QSize(2, 1));
  // Pixel 0: the mean of colours 0 and 1 at full opacity (the most points); pixel 1: colour 2
  // alone (its hidden point left out) at the opacity of one point of two.
  const QColor a = render::category_color(0), b = render::category_color(1);
  EXPECT_TRUE(near(
      colourAt(image, 0, 0),
      QColor((a.red() + b.red()) / 2, (a.green() + b.green()) / 2, (a.blue() + b.blue()) / 2), 2));
  EXPECT_EQ(qAlpha(image.pixel(0, 0)), 255);
  EXPECT_TRUE(near(colourAt(image, 1, 0), render::category_color(2), 2));
  EXPECT_EQ(qAlpha(image.pixel(1, 0)),
            int(std::lround(255 * (0.12 + 0.88 * std::log1p(1.0) / std::log1p(2.0)))));
  EXPECT_THROW(render::category_density_image(points, {0, 1}, QTransform(), QSize(2, 1)),
               ParameterError);
  EXPECT_TRUE(render::category_density_image(points, {0, 0, 0, 0}, QTransform(), QSize()).isNull());
}

}  // namespace
}  // namespace motionmap::studio
