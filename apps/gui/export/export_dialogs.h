#pragma once
// The dialogs of File → Export picture and File → Export animation. Both start filled in: the
// last folder and a name suggested from the clip, method and frame (export_names.h); a name the
// user has not edited follows the choices made in the dialog.
#include <QDialog>

#include "export/animation_export.h"
#include "export/export_names.h"

class QCheckBox;
class QDialogButtonBox;
class QLabel;
class QLineEdit;
class QRadioButton;

namespace motionmap::studio {

/// What to picture (both views, the 3-D view, the map) and the PNG file to write.
class PictureDialog : public QDialog {
  Q_OBJECT
 public:
  PictureDialog(QWidget* parent, const ExportContext& context);
  PictureKind kind() const;
  void setKind(PictureKind kind);
  QString path() const;
  void setPath(const QString& path);
  QLineEdit* pathEdit() const { return m_path; }

 private:
  void kindChanged();

  ExportContext m_context;
  QRadioButton* m_both = nullptr;
  QRadioButton* m_view3d = nullptr;
  QRadioButton* m_map = nullptr;
  QLineEdit* m_path = nullptr;
  QString m_suggested;  ///< the file name suggested last (replaced on a new kind if unedited)
};

/// The folder, the base name, and which of the image sequence and the MP4 to write. Without
/// ffmpeg on PATH the MP4 choice is disabled and the dialog says so.
class AnimationDialog : public QDialog {
  Q_OBJECT
 public:
  /// `ffmpeg`: ffmpeg's path, empty when it is not installed.
  AnimationDialog(QWidget* parent, const ExportContext& context, const QString& ffmpeg);
  AnimationSettings settings() const;
  QLineEdit* folderEdit() const { return m_folder; }
  QLineEdit* nameEdit() const { return m_name; }
  QCheckBox* imagesBox() const { return m_images; }
  QCheckBox* videoBox() const { return m_video; }
  /// The line saying MP4 needs ffmpeg (hidden when it is installed).
  QLabel* ffmpegNote() const { return m_ffmpegNote; }

 private:
  void update();

  ExportContext m_context;
  QLineEdit* m_folder = nullptr;
  QLineEdit* m_name = nullptr;
  QCheckBox* m_images = nullptr;
  QCheckBox* m_video = nullptr;
  QLabel* m_files = nullptr;
  QLabel* m_ffmpegNote = nullptr;
  QDialogButtonBox* m_buttons = nullptr;
};

}  // namespace motionmap::studio
