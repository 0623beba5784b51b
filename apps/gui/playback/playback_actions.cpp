#include "playback/playback_actions.h"

#include <QAction>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QSignalBlocker>

#include "app/help_dialogs.h"
#include "playback/playback.h"

namespace motionmap::studio {

PlaybackActions::PlaybackActions(QMainWindow* window, Playback* playback)
    : QObject(window), m_menu(window->menuBar()->addMenu(tr("&Playback"))) {
  auto add = [&](const QString& text, const QKeySequence& key, const QString& help, auto&& slot) {
    QAction* action = m_menu->addAction(text);
    action->setShortcut(key);
    action->setShortcutContext(Qt::WindowShortcut);
    explain(action, help);
    connect(action, &QAction::triggered, playback, slot);
    // Also the window's own: its shortcuts then hold even where the menu bar is hidden.
    window->addAction(action);
    return action;
  };
  m_playPause =
      add(tr("Play / &pause"), QKeySequence(Qt::Key_Space),
          tr("Plays the motion from the current frame (within the in/out range), or pauses it"),
          [playback] { playback->isPlaying() ? playback->pause() : playback->play(); });
  m_playPause->setAutoRepeat(false);  // a held Space toggles once
  m_menu->addSeparator();
  m_previous = add(tr("P&revious frame"), QKeySequence(Qt::Key_Left),
                   tr("Pauses and steps one frame back"), [playback] { playback->step(-1); });
  m_next = add(tr("&Next frame"), QKeySequence(Qt::Key_Right),
               tr("Pauses and steps one frame forward"), [playback] { playback->step(+1); });
  m_backTen = add(tr("&Back %1 frames").arg(kBigStep), QKeySequence(Qt::SHIFT | Qt::Key_Left),
                  tr("Pauses and steps %1 frames back").arg(kBigStep),
                  [playback] { playback->step(-kBigStep); });
  m_forwardTen =
      add(tr("&Forward %1 frames").arg(kBigStep), QKeySequence(Qt::SHIFT | Qt::Key_Right),
          tr("Pauses and steps %1 frames forward").arg(kBigStep),
          [playback] { playback->step(+kBigStep); });
  m_first = add(tr("Firs&t frame"), QKeySequence(Qt::Key_Home),
                tr("Goes to the in point (the first frame without one); pressed there, to the "
                   "motion's first frame"),
                [playback] { playback->goToStart(); });
  m_last = add(tr("La&st frame"), QKeySequence(Qt::Key_End),
               tr("Goes to the out point (the last frame without one); pressed there, to the "
                  "motion's last frame"),
               [playback] { playback->goToEnd(); });
  m_menu->addSeparator();
  m_setIn = add(tr("Set &in point"), QKeySequence(Qt::Key_I),
                tr("Playback starts and loops back at the current frame"),
                [playback] { playback->setInPoint(playback->frame()); });
  m_setOut = add(tr("Set &out point"), QKeySequence(Qt::Key_O),
                 tr("Playback stops or loops at the current frame"),
                 [playback] { playback->setOutPoint(playback->frame()); });
  m_clearIn = add(tr("Clear in point"), QKeySequence(Qt::ALT | Qt::Key_I),
                  tr("Playback starts at the motion's first frame again"),
                  [playback] { playback->clearInPoint(); });
  m_clearOut = add(tr("Clear out point"), QKeySequence(Qt::ALT | Qt::Key_O),
                   tr("Playback runs to the motion's last frame again"),
                   [playback] { playback->clearOutPoint(); });
  m_menu->addSeparator();
  m_loop = explain(m_menu->addAction(tr("&Loop")),
                   tr("On: playback starts over at the end of the in/out range; off: it stops on "
                      "the range's last frame"));
  m_loop->setCheckable(true);
  m_loop->setChecked(playback->loop());
  connect(m_loop, &QAction::toggled, playback, &Playback::setLoop);
  connect(playback, &Playback::loopChanged, m_loop, [this](bool loop) {
    const QSignalBlocker block(m_loop);
    m_loop->setChecked(loop);
  });
  connect(playback, &Playback::playingChanged, m_playPause,
          [this](bool playing) { m_playPause->setText(playing ? tr("&Pause") : tr("&Play")); });
  m_playPause->setText(playback->isPlaying() ? tr("&Pause") : tr("&Play"));
}

}  // namespace motionmap::studio
