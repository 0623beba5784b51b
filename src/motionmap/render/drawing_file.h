#pragma once
// Writing a drawing to a file, the format from its extension: what every picture MotionMap
// writes (map plots, figures, key-pose sheets) goes through.
#include <functional>
#include <string>

#include <QPainter>
#include <QRectF>
#include <QSize>
#include <QString>

namespace motionmap::render {

/// Throws, rather than let Qt abort (or crash in the font code), when no QGuiApplication exists:
/// drawing text needs the one the caller creates. `caller` starts the message.
/// @throws Error if there is none, or only a QCoreApplication.
void require_gui_application(const char* caller);

/// Opens `path`, runs `draw` on a painter whose coordinates span QRectF(0, 0, size), closes:
/// .png (white background, antialiasing left to `draw`), .svg, .pdf (one page exactly `size`
/// pixels at 96 dpi), case-insensitive. `title` goes into the SVG's and PDF's metadata.
/// @throws Error naming the path and the reason on an unknown extension (checked before anything
///   is created) or a write failure; as require_gui_application(caller).
void write_drawing(const char* caller, const std::string& path, const QSize& size,
                   const QString& title, const std::function<void(QPainter&, const QRectF&)>& draw);

}  // namespace motionmap::render
