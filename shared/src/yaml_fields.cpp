#include "socc/yaml_fields.hpp"

#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <type_traits>
#include <utility>

namespace socc {
namespace {

template <typename T>
const char* expected() {
  if constexpr (std::is_same_v<T, bool>)
    return "true or false";
  else if constexpr (std::is_floating_point_v<T>)
    return "a number";
  else if constexpr (std::is_unsigned_v<T>)
    return "a non-negative integer";  // yaml-cpp refuses "-5" for unsigned types
  else if constexpr (std::is_integral_v<T>)
    return "an integer";
  else
    return "text";
}

// A value as the file spells it; non-scalars (and keys) by their kind.
std::string shown(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  if (node.IsSequence()) return "<sequence>";
  if (node.IsMap()) return "<mapping>";
  return "<empty>";
}

// Every error of one file carries the same "<what> <file>: " prefix.
class Loader {
 public:
  explicit Loader(std::string prefix) : prefix_(std::move(prefix)) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw std::runtime_error(prefix_ + problem);
  }

  // In file order, so the first problem in the file is the one reported.
  void load(const YAML::Node& mapping, const YamlFields& fields, const std::string& section) const {
    for (const auto& entry : mapping) {
      const std::string name = shown(entry.first);
      const std::string key = section + name;
      const YamlField* field = nullptr;
      for (const YamlField& f : fields)
        if (entry.first.IsScalar() && f.key == name) field = &f;
      if (field == nullptr) fail("unknown key '" + key + "'");
      std::visit([&](auto* out) { set(entry.second, key, out); }, field->target);
    }
  }

 private:
  [[noreturn]] void bad(const YAML::Node& value, const std::string& key, const char* want) const {
    fail("key '" + key + "': bad value '" + shown(value) + "' (expected " + want + ")");
  }

  template <typename T>
  void set(const YAML::Node& value, const std::string& key, T* out) const {
    try {
      *out = value.as<T>();
    } catch (const YAML::Exception&) {
      bad(value, key, expected<T>());
    }
  }

  void set(const YAML::Node& value, const std::string& key, std::optional<std::string>* out) const {
    std::string text;
    set(value, key, &text);
    *out = std::move(text);
  }

  void set(const YAML::Node& value, const std::string& key, const YamlFields* section) const {
    if (!value.IsMap()) bad(value, key, "a mapping");
    load(value, *section, key + ".");
  }

  std::string prefix_;
};

}  // namespace

void loadYamlFields(const std::filesystem::path& file, const std::string& what,
                    const YamlFields& fields, const std::function<std::string()>& validate) {
  const Loader loader(what + " " + file.string() + ": ");
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    loader.fail("cannot read the file");
  } catch (const YAML::Exception& e) {
    loader.fail(std::string("not valid YAML: ") + e.what());
  }
  if (!root.IsNull()) {  // an empty file keeps every default
    if (!root.IsMap()) loader.fail("expected a mapping of key: value");
    loader.load(root, fields, "");
  }
  if (!validate) return;
  if (const std::string problem = validate(); !problem.empty()) loader.fail(problem);
}

}  // namespace socc
