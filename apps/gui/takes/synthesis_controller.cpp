#include "takes/synthesis_controller.h"

#include <QMetaObject>

#include "motionmap/core/control.h"
#include "motionmap/core/error.h"
#include "motionmap/synth/path_edit.h"

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
  m_resultKeys = {};
  m_resultKeyFrames.clear();
  m_resultTake = -1;
  m_resultWindow.reset();
}

namespace {

/// The map `supply` gives, made within `control`'s first part when it is not ready (a saved map's
/// blender); `rest` is then the part left for the work on it.
std::shared_ptr<const MapResult> supplied(const MapSupply& supply, const Control& control,
                                          Control& rest) {
  if (supply.ready) {
    rest = control;
    return supply.ready;
  }
  constexpr double kShare = 0.3;  // of the progress bar, for building the blender
  std::shared_ptr<const MapResult> map = supply.make(control.part(0.0, kShare));
  if (!map || !map->blender) throw Error("the map to synthesize on has no blender");
  rest = control.part(kShare, 1.0);
  return map;
}

}  // namespace

bool SynthesisController::start(MapSupply map, const synth::MapPath& path,
                                const SynthParameters& parameters, int take) {
  if (!map || (map.ready && !map.ready->blender)) return false;
  stop();
  m_runningTake = take;
  const synth::SynthOptions options = parameters.motion;
  synth::MapPath followed = path;
  if (!parameters.timedAsDrawn) followed.times.clear();
  // The map the worker synthesized on (made there when it was not ready).
  auto used = std::make_shared<std::shared_ptr<const MapResult>>();
  m_job.start([this, supply = std::move(map), path = std::move(followed), drawn = path, take,
               options, used](const BackgroundJob::Ticket& ticket) {
    runJob<synth::SynthResult>(
        this, m_job, ticket, [this](double fraction, const QString&) { emit progress(fraction); },
        [&](const Control& control) {
          Control rest;
          *used = supplied(supply, control, rest);
          return std::make_shared<synth::SynthResult>(
              synth::synthesize(*(*used)->blender, path, options, rest));
        },
        [this, used, drawn, take](const JobOutcome<synth::SynthResult>& outcome) {
          onResult(*used, drawn, take, nullptr, outcome);
        });
  });
  return true;
}

bool SynthesisController::startEdit(std::shared_ptr<const MapResult> map,
                                    std::shared_ptr<const synth::SynthResult> previous,
                                    const synth::MapPath& path, const SynthParameters& parameters,
                                    int take) {
  if (!map || !map->blender) return false;
  const synth::SynthOptions options = parameters.motion;
  // Only a motion synthesize() made with these options can be edited in part.
  const synth::SynthOptions* was = previous ? &previous->options : nullptr;
  if (!previous || previous->headings.empty() || was->speed != options.speed ||
      was->fps != options.fps || was->smooth != options.smooth ||
      was->clean_feet != options.clean_feet) {
    return start(std::move(map), path, parameters, take);
  }
  stop();
  m_runningTake = take;
  synth::MapPath followed = path;
  if (!parameters.timedAsDrawn) followed.times.clear();
  auto window = std::make_shared<std::pair<int, int>>(0, 0);
  m_job.start([this, map = std::move(map), previous = std::move(previous),
               path = std::move(followed), drawn = path, take,
               window](const BackgroundJob::Ticket& ticket) {
    runJob<synth::SynthResult>(
        this, m_job, ticket, [this](double fraction, const QString&) { emit progress(fraction); },
        [&](const Control& control) {
          synth::PathEditResult edit =
              synth::edit_path(*map->blender, *previous, path, {}, control);
          *window = {edit.first, edit.end};
          return std::make_shared<synth::SynthResult>(std::move(edit.result));
        },
        [this, map, drawn, take, window](const JobOutcome<synth::SynthResult>& outcome) {
          onResult(map, drawn, take, nullptr, outcome, *window);
        });
  });
  return true;
}

bool SynthesisController::startInbetween(MapSupply map, TakeKeys keys,
                                         const SynthParameters& parameters, int take) {
  if (!map || (map.ready && !map.ready->blender) || keys.keys.size() < 2) return false;
  stop();
  m_runningTake = take;
  auto keyed = std::make_shared<Keyed>();
  keyed->keys = std::move(keys);
  synth::InbetweenOptions options;
  options.frames_between = keyed->keys.framesBetween;
  options.clean_feet = parameters.motion.clean_feet;
  options.free_roots = parameters.freeRoots;
  auto used = std::make_shared<std::shared_ptr<const MapResult>>();
  m_job.start([this, supply = std::move(map), keyed, take, options,
               used](const BackgroundJob::Ticket& ticket) {
    runJob<synth::SynthResult>(
        this, m_job, ticket, [this](double fraction, const QString&) { emit progress(fraction); },
        [&](const Control& control) {
          Control rest;
          *used = supplied(supply, control, rest);
          const MapResult& on = **used;
          synth::InbetweenResult r =
              synth::inbetween(*on.blender, *on.map.features, keyed->keys.keys, options, rest);
          auto out = std::make_shared<synth::SynthResult>();
          out->motion = std::move(r.motion);
          out->validity = std::move(r.validity);
          for (const synth::PointValidity& v : out->validity) out->clamped_frames += v.clamped;
          out->notes = std::move(r.notes);
          // The route as the take's path: a point per frame, at the frame rate.
          keyed->path.points = std::move(r.points);
          for (std::size_t k = 0; k < keyed->path.points.size(); ++k)
            keyed->path.times.push_back(double(k) * out->motion.frame_time);
          keyed->keyFrames = std::move(r.key_frames);
          return out;
        },
        [this, used, keyed, take](const JobOutcome<synth::SynthResult>& outcome) {
          onResult(*used, keyed->path, take, keyed, outcome);
        });
  });
  return true;
}

void SynthesisController::onResult(std::shared_ptr<const MapResult> map, synth::MapPath path,
                                   int take, std::shared_ptr<const Keyed> keyed,
                                   const JobOutcome<synth::SynthResult>& outcome,
                                   std::optional<std::pair<int, int>> window) {
  emit stopped();
  if (outcome.cancelled) return emit cancelled();
  if (!outcome.error.isEmpty()) return emit failed(outcome.error);
  m_result = outcome.value;
  m_resultMap = std::move(map);
  m_resultPath = std::move(path);
  m_resultKeys = keyed ? keyed->keys : TakeKeys{};
  m_resultKeyFrames = keyed ? keyed->keyFrames : std::vector<int>{};
  m_resultTake = take;
  m_resultWindow = window;
  emit finished();
}

}  // namespace motionmap::studio
