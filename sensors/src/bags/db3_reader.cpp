// ROS 2 bags in SQLite (.db3): the tables topics (id, name, type, serialization_format) and
// messages (topic_id, timestamp [ns], data), read through libsqlite3, read-only. A blob that is
// a zstd frame (rosbag2's compression_mode "message") is decompressed.
#include <sqlite3.h>

#include <memory>
#include <stdexcept>
#include <unordered_map>

#include "bags/bag_reader.hpp"
#include "bags/decompress.hpp"

namespace socc::sensors::bags {

namespace {

struct SqliteCloser {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
struct StatementFinalizer {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using SqlitePtr = std::unique_ptr<sqlite3, SqliteCloser>;
using StatementPtr = std::unique_ptr<sqlite3_stmt, StatementFinalizer>;

std::string columnText(sqlite3_stmt* s, int column) {
  const auto* text = sqlite3_column_text(s, column);
  return text ? reinterpret_cast<const char*>(text) : "";
}

class Db3Reader : public BagReader {
 public:
  explicit Db3Reader(const std::filesystem::path& file) : file_(file) {
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
    db_.reset(db);
    if (rc != SQLITE_OK) fail("cannot open");
    readTopics();
    prepareMessages(std::nullopt);
  }

  const std::vector<TopicInfo>& topics() const override { return topics_; }

  void select(std::size_t topic) override { prepareMessages(topic_ids_.at(topic)); }

  std::optional<BagMessage> next() override {
    while (messages_) {
      const int rc = sqlite3_step(messages_.get());
      if (rc != SQLITE_ROW) {
        if (rc != SQLITE_DONE) {
          problems_ = "reading messages stopped: " + std::string(sqlite3_errmsg(db_.get())) + "\n";
        }
        messages_.reset();
        break;
      }
      const auto topic = topic_index_.find(sqlite3_column_int64(messages_.get(), 0));
      if (topic == topic_index_.end()) {
        ++unknown_topic_;
        continue;
      }
      BagMessage m;
      m.topic = topic->second;
      m.stamp_ns = sqlite3_column_int64(messages_.get(), 1);
      const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(messages_.get(), 2));
      const ByteView data(blob, static_cast<std::size_t>(sqlite3_column_bytes(messages_.get(), 2)));
      if (!isZstdFrame(data)) {
        m.data.assign(data.data, data.data + data.size);
        return m;
      }
      try {  // rosbag2's compression_mode "message": each blob is one zstd frame
        m.data = decompressZstdFrame(data);
        return m;
      } catch (const FormatError& e) {
        if (bad_frames_++ == 0) first_bad_frame_ = e.what();
      }
    }
    return std::nullopt;
  }

  std::string problems() const override {
    std::string p = problems_;
    if (bad_frames_ > 0) {
      p += std::to_string(bad_frames_) +
           " compressed messages that do not decompress (first: " + first_bad_frame_ + ")\n";
    }
    if (unknown_topic_ > 0) {
      p += std::to_string(unknown_topic_) + " messages of topic ids not in the topics table\n";
    }
    return p;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(file_.string() + ": " + what + " (" +
                             (db_ ? sqlite3_errmsg(db_.get()) : "out of memory") + ")");
  }

  StatementPtr prepare(const char* sql) const {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_.get(), sql, -1, &s, nullptr) != SQLITE_OK) {
      sqlite3_finalize(s);
      fail(std::string("not a ROS 2 bag: ") + sql);
    }
    return StatementPtr(s);
  }

  void readTopics() {
    const StatementPtr s = prepare("SELECT id, name, type, serialization_format FROM topics");
    int rc;
    while ((rc = sqlite3_step(s.get())) == SQLITE_ROW) {
      TopicInfo t;
      t.name = columnText(s.get(), 1);
      t.type = columnText(s.get(), 2);
      t.serialization = columnText(s.get(), 3);
      if (t.serialization == "cdr") t.encoding = Encoding::kCdr;
      topic_index_[sqlite3_column_int64(s.get(), 0)] = topics_.size();
      topic_ids_.push_back(sqlite3_column_int64(s.get(), 0));
      topics_.push_back(std::move(t));
    }
    if (rc != SQLITE_DONE) fail("reading the topics table");
    const StatementPtr counts =
        prepare("SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
    while ((rc = sqlite3_step(counts.get())) == SQLITE_ROW) {
      const auto it = topic_index_.find(sqlite3_column_int64(counts.get(), 0));
      if (it != topic_index_.end()) {
        topics_[it->second].messages =
            static_cast<std::uint64_t>(sqlite3_column_int64(counts.get(), 1));
      }
    }
    if (rc != SQLITE_DONE) fail("counting messages");
  }

  void prepareMessages(std::optional<std::int64_t> topic_id) {
    if (topic_id) {
      messages_ = prepare(
          "SELECT topic_id, timestamp, data FROM messages WHERE topic_id = ? "
          "ORDER BY timestamp, id");
      sqlite3_bind_int64(messages_.get(), 1, *topic_id);
    } else {
      messages_ = prepare("SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id");
    }
  }

  std::filesystem::path file_;
  SqlitePtr db_;
  std::vector<TopicInfo> topics_;
  std::vector<std::int64_t> topic_ids_;
  std::unordered_map<std::int64_t, std::size_t> topic_index_;
  StatementPtr messages_;
  std::string problems_;
  std::uint64_t unknown_topic_ = 0;
  std::uint64_t bad_frames_ = 0;
  std::string first_bad_frame_;
};

}  // namespace

std::unique_ptr<BagReader> openDb3(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) {
    throw std::runtime_error(file.string() + ": no such file");
  }
  return std::make_unique<Db3Reader>(file);
}

}  // namespace socc::sensors::bags
