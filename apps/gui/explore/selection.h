#pragma once
// A selection of a map's frames (a box or a lasso drawn on the map) as plain data: the frames
// inside, grouped per clip into runs of consecutive frames, and written as a clip list
// (`motionmap map @list.txt` reads it: one clip path a line, '#' lines are comments — here each
// clip's selected frame ranges) or as CSV (clip, frame, x, y). No widgets.
#include <functional>
#include <vector>

#include <QPolygonF>
#include <QString>
#include <QStringList>

#include "map/map_source.h"

namespace motionmap::studio {

struct SelectedFrame {
  int clip = 0;
  int frame = 0;
  double x = 0.0, y = 0.0;
};

/// Consecutive frames first..last (inclusive) of one clip.
struct FrameRange {
  int clip = 0;
  int first = 0;
  int last = 0;
  int frames() const { return last - first + 1; }
};

/// The samples whose points lie inside `polygon` (map coordinates; odd-even rule), ordered by
/// clip then frame. Empty for a polygon of fewer than 3 corners or without samples. Linear in
/// the samples (a bounding-box test first). With `shown`, only samples it accepts (those a
/// colouring by label leaves drawn: MapView::sampleShown).
std::vector<SelectedFrame> framesInside(const QPolygonF& polygon, const MapSource::Samples& samples,
                                        const std::function<bool(int sample)>& shown = {});

/// `frames` (ordered by clip and frame) as runs of consecutive frames.
std::vector<FrameRange> frameRanges(const std::vector<SelectedFrame>& frames);

/// "10–80, 120–200" (a single frame: "42").
QString rangesText(const std::vector<FrameRange>& ranges, int clip);

/// A clip list: a comment header, then for each clip with selected frames a comment with its
/// ranges and its file (`files[clip]`) on a line of its own.
QString clipListText(const std::vector<FrameRange>& ranges, const QStringList& files,
                     const QString& from);

/// CSV: "clip,frame,x,y" then one line per frame; clip is the file (`files[clip]`), quoted when
/// it holds a comma or a quote.
QString selectionCsv(const std::vector<SelectedFrame>& frames, const QStringList& files);

}  // namespace motionmap::studio
