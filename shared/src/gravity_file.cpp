#include "socc/gravity_file.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace socc {
namespace {

// strtod, not operator>>: "nan" and "inf" are read, and then refused as not finite.
bool parseNumber(const std::string& token, double& value) {
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return end != token.c_str() && *end == '\0';
}

std::optional<GravityReference> parseGravityLine(const std::string& line, std::string& error) {
  std::istringstream in(line);
  double v[4];
  std::string token;
  for (double& x : v)
    if (!(in >> token) || !parseNumber(token, x)) {
      error = "expected 4 numbers \"ux uy uz sigma_rad\"";
      return std::nullopt;
    }
  if (in >> token) {
    error = "more than 4 values";
    return std::nullopt;
  }
  for (const double x : v)
    if (!std::isfinite(x)) {
      error = "non-finite value";
      return std::nullopt;
    }
  if (v[3] < 0.0) {
    error = "negative sigma";
    return std::nullopt;
  }
  if (v[3] == 0.0) return std::nullopt;  // no reference for this frame
  const Eigen::Vector3d up(v[0], v[1], v[2]);
  if (std::abs(up.norm() - 1.0) > kGravityUnitTolerance) {
    error = "up vector of length " + std::to_string(up.norm()) + " (a unit vector is expected)";
    return std::nullopt;
  }
  return GravityReference{up.normalized(), v[3]};
}

}  // namespace

std::vector<std::optional<GravityReference>> readGravityFile(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::vector<std::optional<GravityReference>> entries;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::string error;
    entries.push_back(parseGravityLine(line, error));
    if (!error.empty())
      throw std::runtime_error(file.string() + ":" + std::to_string(number) + ": " + error);
  }
  return entries;
}

void writeGravityFile(const std::filesystem::path& file,
                      const std::vector<std::optional<GravityReference>>& entries) {
  std::ofstream out(file);
  char line[128];
  for (const auto& g : entries) {
    if (g)
      std::snprintf(line, sizeof(line), "%.9f %.9f %.9f %.6e\n", g->up.x(), g->up.y(), g->up.z(),
                    g->sigma);
    else
      std::snprintf(line, sizeof(line), "0 0 1 0\n");
    out << line;
  }
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
}

}  // namespace socc
