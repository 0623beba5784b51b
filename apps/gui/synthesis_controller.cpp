#include "synthesis_controller.h"

#include <QMetaObject>

#include "motionmap/core/control.h"
#include "motionmap/core/error.h"

namespace motionmap::studio {

SynthesisController::SynthesisController(QObject* parent) : QObject(parent) {}

SynthesisController::~SynthesisController() {
  m_job.stop();
}

bool SynthesisController::stop() {
  if (!m_job.stop()) return false;  // a result still queued from it is ignored from now on
  emit stopped();
  return true;
}

void SynthesisController::cancel() {
  if (!stop()) return;
  emit cancelled();
}

void SynthesisController::clear() {
  m_result.reset();
  m_resultMap.reset();
}

bool SynthesisController::start(std::shared_ptr<const MapResult> map, const synth::MapPath& path,
                                const SynthParameters& parameters) {
  if (!map || !map->blender) return false;
  stop();
  const synth::SynthOptions options = parameters.motion;
  synth::MapPath followed = path;
  if (!parameters.timedAsDrawn) followed.times.clear();
  m_job.start([this, map = std::move(map), path = std::move(followed),
               options](const BackgroundJob::Ticket& ticket) {
    const int generation = ticket.generation;
    auto result = std::make_shared<synth::SynthResult>();
    QString error;
    bool cancelled = false;
    try {
      // Callbacks run on this thread: hand progress to the controller's, read cancel atomically.
      const Control control(
          [this, generation](double fraction, std::string_view) {
            QMetaObject::invokeMethod(
                this,
                [this, generation, fraction] {
                  if (m_job.current(generation)) emit progress(fraction);
                },
                Qt::QueuedConnection);
          },
          [ticket] { return ticket.cancelled(); });
      *result = synth::synthesize(*map->blender, path, options, control);
      if (ticket.cancelled()) throw Cancelled();
    } catch (const Cancelled&) {
      cancelled = true;
    } catch (const std::exception& e) {
      error = QString::fromStdString(e.what());
    }
    QMetaObject::invokeMethod(
        this,
        [this, generation, map, result, error, cancelled] {
          onResult(generation, map, result, error, cancelled);
        },
        Qt::QueuedConnection);
  });
  return true;
}

void SynthesisController::onResult(int generation, std::shared_ptr<const MapResult> map,
                                   std::shared_ptr<synth::SynthResult> result, QString error,
                                   bool cancelled) {
  if (!m_job.current(generation)) return;  // stopped, or replaced by a newer sketch
  m_job.finish();
  emit stopped();
  if (cancelled) return emit this->cancelled();
  if (!error.isEmpty()) return emit failed(error);
  m_result = std::move(*result);
  m_resultMap = std::move(map);
  emit finished();
}

}  // namespace motionmap::studio
