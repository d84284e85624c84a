#pragma once
// One loader for the YAML configuration files (map grid, map service, odometry): each config
// lists its keys with the variable each one sets, so unknown keys, wrong types and range
// problems are reported the same way everywhere. yaml-cpp stays inside yaml_fields.cpp.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace socc {

struct YamlField;
/// A config's keys. A key the file does not name keeps its variable's value (the default).
using YamlFields = std::vector<YamlField>;

struct YamlField {
  /// Where the value goes. Pointers to variables rather than to members, so a loader can also
  /// read into locals (paths it resolves afterwards). optional<string>: text whose presence
  /// matters; const YamlFields*: a nested section (a mapping, its keys named "section.key").
  using Target = std::variant<bool*, int*, std::int64_t*, std::size_t*, double*, std::string*,
                              std::optional<std::string>*, const YamlFields*>;
  std::string key;
  Target target;
};

/// Sets the fields `file` names (an empty file names none), then runs validate (if given): a
/// non-empty answer is the problem. Throws std::runtime_error "<what> <file>: <problem>", the
/// problem being "cannot read the file", "not valid YAML: ...", "expected a mapping of key:
/// value", "unknown key 'k'", "key 'k': bad value 'v' (expected a number)" (or an integer, a
/// non-negative integer, true or false, text, a mapping) or validate's answer.
void loadYamlFields(const std::filesystem::path& file, const std::string& what,
                    const YamlFields& fields, const std::function<std::string()>& validate = {});

}  // namespace socc
