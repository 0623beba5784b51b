#include "takes/synthesis_controller.h"

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
  m_resultPath = {};
  m_resultTake = -1;
}

bool SynthesisController::start(std::shared_ptr<const MapResult> map, const synth::MapPath& path,
                                const SynthParameters& parameters, int take) {
  if (!map || !map->blender) return false;
  stop();
  m_runningTake = take;
  const synth::SynthOptions options = parameters.motion;
  synth::MapPath followed = path;
  if (!parameters.timedAsDrawn) followed.times.clear();
  m_job.start([this, map = std::move(map), path = std::move(followed), drawn = path, take,
               options](const BackgroundJob::Ticket& ticket) {
    runJob<synth::SynthResult>(
        this, m_job, ticket, [this](double fraction, const QString&) { emit progress(fraction); },
        [&](const Control& control) {
          return std::make_shared<synth::SynthResult>(
              synth::synthesize(*map->blender, path, options, control));
        },
        [this, map, drawn, take](const JobOutcome<synth::SynthResult>& outcome) {
          onResult(map, drawn, take, outcome);
        });
  });
  return true;
}

void SynthesisController::onResult(std::shared_ptr<const MapResult> map, synth::MapPath path,
                                   int take, const JobOutcome<synth::SynthResult>& outcome) {
  emit stopped();
  if (outcome.cancelled) return emit cancelled();
  if (!outcome.error.isEmpty()) return emit failed(outcome.error);
  m_result = outcome.value;
  m_resultMap = std::move(map);
  m_resultPath = std::move(path);
  m_resultTake = take;
  emit finished();
}

}  // namespace motionmap::studio
