#include "socc/pcd_header.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace socc {

namespace {

// Key -> values of each header line up to DATA.
using PcdHeader = std::map<std::string, std::vector<std::string>>;

[[noreturn]] void headerError(const std::filesystem::path& file, const std::string& why) {
  throw std::runtime_error(file.string() + ": " + why);
}

bool parseCount(const std::string& text, unsigned long long& value) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 12)
    return false;
  value = std::stoull(text);
  return true;
}

constexpr const char* kKeys[] = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                 "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};

// PCL's header loop does not stop at DATA: it goes on reading lines of the body while they are
// blank, comments or start with a header key, and a key line there rewrites the header it has
// already used (a binary body starting with "COLUMNS" frees the fields: use after free). Such a
// body is refused.
void checkBodyStart(const std::filesystem::path& file, std::istream& in) {
  for (std::string line; std::getline(in, line);) {
    std::istringstream tokens(line);
    std::string first;
    if (!(tokens >> first) || first[0] == '#') continue;
    const auto starts_with = [&first](const char* key) { return first.rfind(key, 0) == 0; };
    if (std::any_of(std::begin(kKeys), std::end(kKeys), starts_with) || starts_with("COLUMNS"))
      headerError(file, "PCD body starts with a header line (" + first.substr(0, 16) + ")");
    return;
  }
}

// The header lines up to DATA (at most 64, known keys only); header_bytes is their size.
PcdHeader readHeaderLines(const std::filesystem::path& file, std::uintmax_t& header_bytes) {
  std::ifstream in(file, std::ios::binary);
  if (!in) headerError(file, "cannot open");
  PcdHeader header;
  header_bytes = 0;
  std::string line;
  for (int n = 0; n < 64 && header.count("DATA") == 0 && std::getline(in, line); ++n) {
    header_bytes += line.size() + 1;
    std::istringstream tokens(line);
    std::string key;
    if (!(tokens >> key) || key[0] == '#') continue;
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys))
      headerError(file, "not a PCD file (unexpected header line '" + line.substr(0, 40) + "')");
    std::vector<std::string>& values = header[key];
    for (std::string v; tokens >> v;) values.push_back(v);
  }
  for (const char* key : {"FIELDS", "SIZE", "TYPE", "WIDTH", "POINTS", "DATA"})
    if (header.count(key) == 0)
      headerError(file, std::string("PCD header has no ") + key + " line");
  checkBodyStart(file, in);  // only a file with a DATA line has a body
  return header;
}

// Bytes per point, once FIELDS, SIZE, TYPE and COUNT agree and hold valid values.
unsigned long long pointBytes(const std::filesystem::path& file, PcdHeader& header) {
  const std::size_t num_fields = header["FIELDS"].size();
  const bool has_count = header.count("COUNT") != 0;
  if (num_fields == 0 || header["SIZE"].size() != num_fields ||
      header["TYPE"].size() != num_fields || (has_count && header["COUNT"].size() != num_fields))
    headerError(file, "PCD header: FIELDS, SIZE, TYPE and COUNT disagree");
  unsigned long long point_bytes = 0;
  for (std::size_t i = 0; i < num_fields; ++i) {
    unsigned long long size = 0, count = 1;
    const std::string& type = header["TYPE"][i];
    if (!parseCount(header["SIZE"][i], size) ||
        (size != 1 && size != 2 && size != 4 && size != 8) ||
        (type != "I" && type != "U" && type != "F") ||
        (has_count && (!parseCount(header["COUNT"][i], count) || count == 0 || count > 1024)))
      headerError(file, "PCD header: bad SIZE/TYPE/COUNT of field " + header["FIELDS"][i]);
    point_bytes += size * count;
  }
  return point_bytes;
}

// POINTS, once WIDTH * HEIGHT equals it.
unsigned long long pointCount(const std::filesystem::path& file, PcdHeader& header) {
  unsigned long long width = 0, height = 1, points = 0;
  if (header["WIDTH"].size() != 1 || !parseCount(header["WIDTH"][0], width) ||
      header["POINTS"].size() != 1 || !parseCount(header["POINTS"][0], points) ||
      (header.count("HEIGHT") != 0 &&
       (header["HEIGHT"].size() != 1 || !parseCount(header["HEIGHT"][0], height))) ||
      height == 0 || points % height != 0 || points / height != width)  // no overflow
    headerError(file, "PCD header: WIDTH * HEIGHT must equal POINTS");
  return points;
}

}  // namespace

void checkPcdHeader(const std::filesystem::path& file) {
  std::uintmax_t header_bytes = 0;
  PcdHeader header = readHeaderLines(file, header_bytes);
  const unsigned long long point_bytes = pointBytes(file, header);
  const unsigned long long points = pointCount(file, header);
  const std::vector<std::string>& data = header["DATA"];
  if (data.size() != 1 ||
      (data[0] != "ascii" && data[0] != "binary" && data[0] != "binary_compressed"))
    headerError(file, "PCD header: DATA must be ascii, binary or binary_compressed");
  // PCL allocates POINTS * point size before reading the body: bound it by what the file can
  // hold (ascii: at least 2 characters per point; LZF expands at most ~100x).
  const std::uintmax_t file_bytes = std::filesystem::file_size(file);
  const std::uintmax_t body_bytes = file_bytes > header_bytes ? file_bytes - header_bytes : 0;
  if (points > (1ull << 32) || point_bytes > (1ull << 16))
    headerError(file, "PCD header: too many points or too large points");
  const unsigned long long claimed = points * point_bytes;
  if ((data[0] == "binary" && body_bytes < claimed) ||
      (data[0] == "ascii" && body_bytes < 2 * points) ||
      (data[0] == "binary_compressed" && claimed > 100 * body_bytes + 1024))
    headerError(file, "PCD file is too short for its POINTS");
}

}  // namespace socc
