// Opening a bag by its path, and ROS 2 bag folders (metadata.yaml + one or more storage files)
// as one reader over their files in order.
#include "bags/bag_reader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <stdexcept>

namespace socc::sensors::bags {

namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::unique_ptr<BagReader> openStorageFile(const fs::path& file) {
  const std::string ext = lowerExtension(file);
  if (ext == ".db3") return openDb3(file);
  if (ext == ".mcap") return openMcap(file);
  throw std::runtime_error(file.string() + ": not a ROS 2 storage file (.db3 or .mcap)");
}

/// The storage files of a ROS 2 bag folder: metadata.yaml's relative_file_paths, or without
/// it every .db3 / .mcap file in name order.
std::vector<fs::path> ros2BagFiles(const fs::path& folder) {
  std::vector<fs::path> files;
  const fs::path metadata = folder / "metadata.yaml";
  if (fs::exists(metadata)) {
    try {
      const YAML::Node info = YAML::LoadFile(metadata.string())["rosbag2_bagfile_information"];
      const std::string compression = info["compression_format"].as<std::string>("");
      const std::string mode = info["compression_mode"].as<std::string>("");
      // Per-message zstd is decompressed by the .db3 reader; whole compressed files are not read.
      if (!compression.empty() && !(compression == "zstd" && mode == "message")) {
        throw std::runtime_error(metadata.string() + ": ROS 2 bags compressed with " + compression +
                                 " in mode " + mode + " are not supported (only zstd per message)");
      }
      for (const YAML::Node& f : info["relative_file_paths"])
        files.push_back(folder / f.as<std::string>());
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(metadata.string() + ": " + e.what());
    }
  } else {
    for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
      const std::string ext = lowerExtension(e.path());
      if (ext == ".db3" || ext == ".mcap") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
  }
  if (files.empty()) throw std::runtime_error(folder.string() + ": no .db3 or .mcap files");
  return files;
}

/// The files of a split bag, one after the other; topics are merged by name.
class ChainedReader : public BagReader {
 public:
  explicit ChainedReader(std::vector<fs::path> files) : files_(std::move(files)) {
    for (const fs::path& f : files_) {
      const std::unique_ptr<BagReader> reader = openStorageFile(f);
      std::vector<std::size_t> map;
      for (const TopicInfo& t : reader->topics()) map.push_back(merge(t));
      topic_maps_.push_back(std::move(map));
    }
    current_ = openStorageFile(files_[0]);
  }

  const std::vector<TopicInfo>& topics() const override { return topics_; }

  void select(std::size_t topic) override {
    selected_ = topic;
    applySelection();
  }

  std::optional<BagMessage> next() override {
    while (current_) {
      if (std::optional<BagMessage> m = current_->next()) {
        m->topic = topic_maps_[file_][m->topic];
        return m;
      }
      problems_ += current_->problems();
      current_.reset();
      if (++file_ < files_.size()) {
        current_ = openStorageFile(files_[file_]);
        applySelection();
      }
    }
    return std::nullopt;
  }

  std::string problems() const override {
    return problems_ + (current_ ? current_->problems() : std::string());
  }

 private:
  std::size_t merge(const TopicInfo& t) {
    for (std::size_t i = 0; i < topics_.size(); ++i) {
      if (topics_[i].name == t.name) {
        topics_[i].messages += t.messages;
        return i;
      }
    }
    topics_.push_back(t);
    return topics_.size() - 1;
  }

  void applySelection() {
    if (!selected_ || !current_) return;
    const std::vector<std::size_t>& map = topic_maps_[file_];
    const auto it = std::find(map.begin(), map.end(), *selected_);
    if (it == map.end()) {
      current_.reset();  // this file has no message of the topic; next() moves on
      if (++file_ < files_.size()) {
        current_ = openStorageFile(files_[file_]);
        applySelection();
      }
      return;
    }
    current_->select(static_cast<std::size_t>(it - map.begin()));
  }

  std::vector<fs::path> files_;
  std::vector<TopicInfo> topics_;
  std::vector<std::vector<std::size_t>> topic_maps_;  // per file: its topic index -> merged
  std::size_t file_ = 0;
  std::unique_ptr<BagReader> current_;
  std::optional<std::size_t> selected_;
  std::string problems_;
};

}  // namespace

std::unique_ptr<BagReader> openRos2Bag(const fs::path& path) {
  if (!fs::is_directory(path)) return openStorageFile(path);
  std::vector<fs::path> files = ros2BagFiles(path);
  if (files.size() == 1) return openStorageFile(files[0]);
  return std::make_unique<ChainedReader>(std::move(files));
}

bool hasBagExtension(const fs::path& file) {
  const std::string ext = lowerExtension(file);
  return ext == ".bag" || ext == ".db3" || ext == ".mcap";
}

std::unique_ptr<BagReader> openBagReader(const fs::path& path) {
  if (fs::is_directory(path)) return openRos2Bag(path);
  if (!fs::exists(path)) throw std::runtime_error(path.string() + ": no such file");
  const std::string ext = lowerExtension(path);
  if (ext == ".bag") return openRos1Bag(path);
  if (ext == ".db3" || ext == ".mcap") return openStorageFile(path);
  throw std::runtime_error(path.string() + ": not a bag (.bag, .db3, .mcap or a ROS 2 bag folder)");
}

std::string describeTopics(const std::vector<TopicInfo>& topics) {
  if (topics.empty()) return "  (no topics)\n";
  std::string s;
  for (const TopicInfo& t : topics) {
    s += "  " + t.name + "  " + t.type;
    if (t.messages > 0) s += "  (" + std::to_string(t.messages) + " messages)";
    s += "\n";
  }
  return s;
}

}  // namespace socc::sensors::bags
