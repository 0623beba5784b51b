#include "export/export_dialogs.h"

#include <QCheckBox>
#include <QDialogButtonBox>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QRadioButton>
#include <QVBoxLayout>

namespace motionmap::studio {

namespace {
QString folderOf(const ExportContext& context) {
  return context.folder.isEmpty() ? QDir::currentPath() : context.folder;
}
/// A line edit with a Browse… button beside it that runs `browse` and takes what it returns.
QWidget* withBrowse(QLineEdit* edit, const QString& tip, const std::function<QString()>& browse) {
  auto* row = new QWidget;
  auto* layout = new QHBoxLayout(row);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(edit, 1);
  auto* button = new QPushButton(QDialog::tr("Browse…"));
  button->setToolTip(tip);
  layout->addWidget(button);
  QObject::connect(button, &QPushButton::clicked, edit, [edit, browse] {
    const QString chosen = browse();
    if (!chosen.isEmpty()) edit->setText(chosen);
  });
  return row;
}
}  // namespace

PictureDialog::PictureDialog(QWidget* parent, const ExportContext& context)
    : QDialog(parent), m_context(context) {
  setWindowTitle(tr("Export picture"));
  auto* layout = new QVBoxLayout(this);
  m_both = new QRadioButton(tr("&Both views side by side"));
  m_both->setToolTip(tr("The 3-D view and the map with its pointer, as in the window"));
  m_view3d = new QRadioButton(tr("The &3-D view"));
  m_view3d->setToolTip(tr("The skeleton at the frame shown, at the view's size"));
  m_map = new QRadioButton(tr("The &map"));
  m_map->setToolTip(
      tr("The map view as shown: the trajectory red → blue and the pointer on the frame shown "
         "(File → Export map writes the map alone, with its parameters, as PNG, SVG or CSV)"));
  m_both->setChecked(true);
  for (QRadioButton* b : {m_both, m_view3d, m_map}) {
    layout->addWidget(b);
    connect(b, &QRadioButton::toggled, this, [this](bool on) {
      if (on) kindChanged();
    });
  }
  m_path = new QLineEdit;
  m_path->setToolTip(tr("The PNG file to write"));
  m_path->setMinimumWidth(420);
  auto* form = new QFormLayout;
  form->addRow(tr("&File:"), withBrowse(m_path, tr("Choose the file in a file dialog"), [this] {
                 return QFileDialog::getSaveFileName(this, tr("Export picture"), m_path->text(),
                                                     tr("PNG image (*.png)"));
               }));
  layout->addLayout(form);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Save | QDialogButtonBox::Cancel);
  buttons->button(QDialogButtonBox::Save)->setToolTip(tr("Write the picture as PNG"));
  buttons->button(QDialogButtonBox::Cancel)->setToolTip(tr("Close without writing"));
  connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(m_path, &QLineEdit::textChanged, this, [this, buttons](const QString& text) {
    buttons->button(QDialogButtonBox::Save)->setEnabled(!text.trimmed().isEmpty());
  });
  layout->addWidget(buttons);
  m_suggested = pictureFileName(m_context.naming, PictureKind::Both);
  m_path->setText(QDir(folderOf(m_context)).filePath(m_suggested));
}

PictureKind PictureDialog::kind() const {
  if (m_view3d->isChecked()) return PictureKind::View3D;
  if (m_map->isChecked()) return PictureKind::Map;
  return PictureKind::Both;
}

void PictureDialog::setKind(PictureKind kind) {
  (kind == PictureKind::View3D ? m_view3d
   : kind == PictureKind::Map  ? m_map
                               : m_both)
      ->setChecked(true);
}

QString PictureDialog::path() const {
  return m_path->text().trimmed();
}

void PictureDialog::setPath(const QString& path) {
  m_path->setText(path);
}

void PictureDialog::kindChanged() {
  const QFileInfo info(path());
  const QString suggested = pictureFileName(m_context.naming, kind());
  // A name the user typed stays; the suggestion follows the choice.
  if (info.fileName() == m_suggested) m_path->setText(info.dir().filePath(suggested));
  m_suggested = suggested;
}

AnimationDialog::AnimationDialog(QWidget* parent, const ExportContext& context,
                                 const QString& ffmpeg)
    : QDialog(parent), m_context(context) {
  setWindowTitle(tr("Export animation"));
  auto* layout = new QVBoxLayout(this);
  const int frames = context.last - context.first + 1;
  auto* range = new QLabel(tr("Frames %1–%2 of the motion playing: %3 frames at %4 fps (%5 s), "
                              "rendered one by one as the window shows them: the 3-D view with "
                              "the map and its pointer beside it.")
                               .arg(context.first)
                               .arg(context.last)
                               .arg(frames)
                               .arg(context.fps, 0, 'g', 4)
                               .arg(context.fps > 0 ? frames / context.fps : 0.0, 0, 'f', 2));
  range->setWordWrap(true);
  layout->addWidget(range);

  auto* form = new QFormLayout;
  m_folder = new QLineEdit(folderOf(context));
  m_folder->setToolTip(tr("The folder the files are written to (created when missing)"));
  m_folder->setMinimumWidth(420);
  form->addRow(
      tr("F&older:"), withBrowse(m_folder, tr("Choose the folder in a file dialog"), [this] {
        return QFileDialog::getExistingDirectory(this, tr("Export animation to"), m_folder->text());
      }));
  m_name = new QLineEdit(animationName(context.naming));
  m_name->setToolTip(tr("The files' name: NAME_0000.png … and NAME.mp4"));
  form->addRow(tr("&Name:"), m_name);
  layout->addLayout(form);

  m_images = new QCheckBox(tr("PNG &image sequence"));
  m_images->setToolTip(
      tr("One PNG per frame, numbered from 0000 (the first frame exported) in frame order"));
  m_images->setChecked(true);
  m_video = new QCheckBox(tr("MP4 &video (H.264)"));
  m_video->setToolTip(
      tr("Encoded by ffmpeg: H.264, yuv420p, at the motion's frame rate; an odd last pixel "
         "column or row is dropped (H.264 in yuv420p needs an even size)"));
  m_ffmpegNote = new QLabel(tr("MP4 needs ffmpeg (Debian package ffmpeg); image sequence only."));
  m_ffmpegNote->setToolTip(tr("Install it (apt-get install ffmpeg) and open this dialog again"));
  m_ffmpegNote->setWordWrap(true);
  if (ffmpeg.isEmpty()) {
    m_video->setEnabled(false);
    m_video->setChecked(false);
  } else {
    m_video->setChecked(true);
    m_video->setToolTip(m_video->toolTip() + tr(" (%1)").arg(ffmpeg));
    m_ffmpegNote->hide();
  }
  layout->addWidget(m_images);
  layout->addWidget(m_video);
  layout->addWidget(m_ffmpegNote);
  m_files = new QLabel;
  m_files->setWordWrap(true);
  m_files->setToolTip(tr("The files the export writes"));
  layout->addWidget(m_files);

  m_buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  m_buttons->button(QDialogButtonBox::Ok)->setText(tr("&Export"));
  m_buttons->button(QDialogButtonBox::Ok)
      ->setToolTip(tr("Render and write the frames, with a progress dialog and Cancel"));
  m_buttons->button(QDialogButtonBox::Cancel)->setToolTip(tr("Close without writing"));
  connect(m_buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(m_buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  layout->addWidget(m_buttons);
  for (QLineEdit* edit : {m_folder, m_name})
    connect(edit, &QLineEdit::textChanged, this, &AnimationDialog::update);
  for (QCheckBox* box : {m_images, m_video})
    connect(box, &QCheckBox::toggled, this, &AnimationDialog::update);
  update();
}

AnimationSettings AnimationDialog::settings() const {
  AnimationSettings s;
  s.folder = m_folder->text().trimmed();
  s.name = m_name->text().trimmed();
  s.images = m_images->isChecked();
  s.video = m_video->isEnabled() && m_video->isChecked();
  s.first = m_context.first;
  s.last = m_context.last;
  return s;
}

void AnimationDialog::update() {
  const AnimationSettings s = settings();
  const int frames = s.last - s.first + 1;
  QStringList files;
  if (s.images) {
    files << tr("%1 … %2").arg(sequenceFileName(s.name, 0, frames),
                               sequenceFileName(s.name, frames - 1, frames));
  }
  if (s.video) files << s.name + ".mp4";
  m_files->setText(files.isEmpty() ? tr("Choose the image sequence, the video or both.")
                                   : tr("Writes %1.").arg(files.join(tr(" and "))));
  m_buttons->button(QDialogButtonBox::Ok)
      ->setEnabled(!files.isEmpty() && !s.name.isEmpty() && !s.folder.isEmpty() && frames > 0);
}

}  // namespace motionmap::studio
