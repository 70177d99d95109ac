// The metrics of a set of centre and point samples, whole and per laser plane, for
// EvaluateRun (eval_metrics.h). Internal to eval_metrics.cpp; defined in eval_summary.cpp.
#pragma once

#include <map>
#include <optional>
#include <vector>

#include "pipeline/eval_metrics.h"

namespace lt::eval_detail {

// The metrics of the samples (of plane `plane` when set: true plane for
// ground-truth centres, measured plane for false positives and points).
EvalSummary Summarise(const std::vector<CenterSample>& centers, const std::vector<PointSample>& points,
                      std::optional<int> plane = std::nullopt);

// Summarise per plane (the planes the samples name).
std::map<int, EvalSummary> SummarisePlanes(const std::vector<CenterSample>& centers,
                                           const std::vector<PointSample>& points);

}  // namespace lt::eval_detail
