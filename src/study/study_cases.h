// A study's cases run, surface by surface ((s, b) in the plan's order): one truth per (s, b),
// reused for every view of it; the cases of a surface in a pipeline, at most one in flight
// per core, grazing views first (the costliest, so that the surface ends on cheap ones), each
// rendered, its GLSL methods drawn and its C++ methods timed, then handed on in that order the
// moment it and the cases before it are done (so a kill loses at most the cases in flight). GLSL
// methods are timed once per view direction (Study::timing.glPerView), with nothing beside
// them; draws and C++ timings never overlap (docs/studies.md).
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/clock.h"
#include "frame/render.h"
#include "scene/scene.h"
#include "study/plan.h"

namespace pgt {

// The view of one case: the scene's camera at the case's angles and the study's frame.
ViewSpec caseView(const Scene& scene, const Study& study, const StudyCase& c);

struct CaseOptions {
    std::string imagesDir;  // non-empty: each case's files in DIR/images/case_NNNNN/
};
// Called on one thread, in case order, with each finished case (its timing in).
using CaseDone = std::function<void(const StudyCase&, const RenderResult&)>;
// Wall ms per stage, summed over the cases and phases.

// Runs `todo` (cases of `study`, grouped by (s, b) as the plan lists them).
void runStudyCases(const Scene& scene, const Study& study,
                   const std::vector<const StudyCase*>& todo, const CaseOptions& opt,
                   const CaseDone& done, StageTimes& stages);

}  // namespace pgt
