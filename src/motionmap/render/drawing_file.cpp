#include "motionmap/render/drawing_file.h"

#include <cctype>
#include <filesystem>

#include <QCoreApplication>
#include <QFile>
#include <QGuiApplication>
#include <QImage>
#include <QImageWriter>
#include <QPageSize>
#include <QPdfWriter>
#include <QSvgGenerator>

#include "motionmap/core/error.h"

namespace motionmap::render {
namespace {

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

enum class Format { Png, Svg, Pdf };

Error write_error(const std::string& path, const std::string& reason) {
  return Error("cannot write '" + path + "': " + reason);
}

Format format_of(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".png") return Format::Png;
  if (ext == ".svg") return Format::Svg;
  if (ext == ".pdf") return Format::Pdf;
  throw write_error(
      path, (ext.empty() ? std::string("no file extension") : "unknown extension '" + ext + "'") +
                " (expected .png, .svg or .pdf)");
}

}  // namespace

void require_gui_application(const char* caller) {
  const QCoreApplication* app = QCoreApplication::instance();
  if (app == nullptr) {
    throw Error(std::string(caller) +
                ": no QGuiApplication exists; create one before drawing (the render library "
                "draws into what it is given and never creates the application)");
  }
  if (qobject_cast<const QGuiApplication*>(app) == nullptr) {
    throw Error(std::string(caller) +
                ": a QCoreApplication exists, but drawing needs a QGuiApplication (create one "
                "instead)");
  }
}

void write_drawing(const char* caller, const std::string& path, const QSize& size,
                   const QString& title,
                   const std::function<void(QPainter&, const QRectF&)>& draw) {
  const Format format = format_of(path);  // before creating anything
  require_gui_application(caller);
  const QString qpath = QString::fromStdString(path);
  const QRectF area(QPointF(0, 0), QSizeF(size));

  if (format == Format::Png) {
    QImage image(size, QImage::Format_RGB32);
    if (image.isNull()) throw write_error(path, "cannot allocate the image");
    image.fill(Qt::white);
    {
      QPainter painter(&image);
      draw(painter, area);
    }
    QImageWriter writer(qpath, "png");
    if (!writer.write(image)) throw write_error(path, writer.errorString().toStdString());
    return;
  }

  QFile file(qpath);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate)) {
    throw write_error(path, file.errorString().toStdString());
  }
  if (format == Format::Svg) {
    QSvgGenerator svg;
    svg.setOutputDevice(&file);
    svg.setSize(size);
    svg.setViewBox(QRect(QPoint(0, 0), size));
    svg.setResolution(96);  // the same physical size as the PDF
    svg.setTitle(title);
    svg.setDescription(QStringLiteral("MotionMap"));
    QPainter painter;
    if (!painter.begin(&svg)) throw write_error(path, "cannot start the SVG painter");
    draw(painter, area);
    painter.end();
  } else {
    QPdfWriter pdf(&file);
    pdf.setCreator(QStringLiteral("MotionMap"));
    pdf.setTitle(title);
    pdf.setResolution(96);
    // One page exactly the figure's size: size px at 96 dpi = size · 72/96 pt.
    pdf.setPageSize(QPageSize(QSizeF(size) * (72.0 / 96.0), QPageSize::Point, QString(),
                              QPageSize::ExactMatch));
    pdf.setPageMargins(QMarginsF(0, 0, 0, 0));
    QPainter painter;
    if (!painter.begin(&pdf)) throw write_error(path, "cannot start the PDF painter");
    // The page in device pixels may differ from `size` by rounding; draw in `size` units.
    painter.scale(painter.device()->width() / area.width(),
                  painter.device()->height() / area.height());
    draw(painter, area);
    painter.end();
  }
  file.close();
  if (file.error() != QFileDevice::NoError) {
    throw write_error(path, file.errorString().toStdString());
  }
}

}  // namespace motionmap::render
