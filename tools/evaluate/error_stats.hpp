#pragma once
#include <cstddef>
#include <vector>

namespace dammloam::eval {

// Summary of a list of error magnitudes, defined as evo does (std is the population std,
// median averages the two middle values of an even count). All NaN when there are no errors.
struct ErrorStats {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;  // sum of squared errors
  std::size_t count = 0;
};

ErrorStats ComputeStats(std::vector<double> errors);

}  // namespace dammloam::eval
