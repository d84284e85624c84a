#pragma once
// Summary statistics of a list of per-pose errors, as evo reports them (std is the population
// standard deviation, median the mean of the two middle values for even counts).
#include <cstddef>
#include <vector>

namespace socc::eval {

struct ErrorStatistics {
  std::size_t count = 0;
  double mean = 0.0;
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
  double rmse = 0.0;
  double std = 0.0;
};

/// Throws std::invalid_argument on an empty list.
ErrorStatistics computeStatistics(const std::vector<double>& errors);

}  // namespace socc::eval
