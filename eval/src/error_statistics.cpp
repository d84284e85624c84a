#include "socc/eval/error_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace socc::eval {

ErrorStatistics computeStatistics(const std::vector<double>& errors) {
  if (errors.empty()) throw std::invalid_argument("no errors to summarise");
  ErrorStatistics s;
  s.count = errors.size();
  const double n = static_cast<double>(errors.size());
  s.mean = std::accumulate(errors.begin(), errors.end(), 0.0) / n;
  double squares = 0.0;
  double centred = 0.0;
  for (const double e : errors) {
    squares += e * e;
    centred += (e - s.mean) * (e - s.mean);
  }
  s.rmse = std::sqrt(squares / n);
  s.std = std::sqrt(centred / n);
  const auto [lo, hi] = std::minmax_element(errors.begin(), errors.end());
  s.min = *lo;
  s.max = *hi;
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t mid = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

}  // namespace socc::eval
