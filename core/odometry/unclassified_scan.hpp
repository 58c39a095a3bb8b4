#pragma once

#include "core/geometry/scan.hpp"
#include "core/preprocess/classified_scan.hpp"
#include "core/preprocess/preprocess_config.hpp"

namespace dammloam {

// The point-to-point ablation needs no features: validate the scan (finite, in range) like
// the feature stage does and label every point Unknown with a zero normal.
ClassifiedScan UnclassifiedScan(Scan scan, const PreprocessConfig& config,
                                const SensorModel& sensor);

}  // namespace dammloam
