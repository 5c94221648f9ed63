#include "cogmap/io/ros2_bag.h"

#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "cogmap/core/error.h"
#include "cogmap/io/cdr.h"
#include "cogmap/io/ros_log.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;

std::string Trim(std::string s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r");
  s = s.substr(a, b - a + 1);
  if (s.size() >= 2 && (s[0] == '\'' || s[0] == '"') && s.back() == s[0]) s = s.substr(1, s.size() - 2);
  return s;
}

size_t Indent(const std::string& line) {
  const auto a = line.find_first_not_of(' ');
  return a == std::string::npos ? line.size() : a;
}

// The storage and the .db3 files of a bag folder, from its metadata.yaml
// (rosbag2's format: 'storage_identifier: sqlite3' and the list under
// 'relative_file_paths:').
struct Metadata {
  std::string storage;
  std::vector<std::string> files;
};

Metadata ReadMetadata(const fs::path& yaml) {
  std::ifstream in(yaml);
  if (!in) throw InputError(yaml.string(), 0, "cannot open");
  Metadata m;
  std::string line;
  long n = 0;
  size_t list_indent = std::string::npos;
  while (std::getline(in, line)) {
    ++n;
    const std::string t = Trim(line);
    if (t.empty() || t[0] == '#') continue;
    if (list_indent != std::string::npos) {
      if (Indent(line) >= list_indent && t.rfind("- ", 0) == 0) {
        m.files.push_back(Trim(t.substr(2)));
        continue;
      }
      list_indent = std::string::npos;
    }
    if (t.rfind("storage_identifier:", 0) == 0) m.storage = Trim(t.substr(19));
    if (t.rfind("relative_file_paths:", 0) == 0) {
      if (!Trim(t.substr(20)).empty() && Trim(t.substr(20)) != "[]")
        throw InputError(yaml.string(), n, "relative_file_paths: expected a block list ('- file.db3' lines)");
      list_indent = Indent(line) + 1;
    }
  }
  if (m.storage.empty()) throw InputError(yaml.string(), 0, "no storage_identifier: not a rosbag2 metadata.yaml");
  return m;
}

[[noreturn]] void McapError(const std::string& path) {
  throw InputError(path + ": a ROS 2 bag in the MCAP storage: cogmap reads the sqlite3 storage only (convert it with "
                          "'ros2 bag convert' to storage_id sqlite3)");
}

class Db {
 public:
  explicit Db(const std::string& path) : path_(path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError(path, 0, "cannot open: no such file");
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) Fail("cannot open");
  }
  ~Db() { sqlite3_close(db_); }
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;
  sqlite3* get() const { return db_; }
  const std::string& path() const { return path_; }
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(path_ + ": " + what + " (SQLite: " + (db_ ? sqlite3_errmsg(db_) : "no memory") +
                     "; a ROS 2 sqlite3 bag has tables topics and messages)");
  }
  sqlite3_stmt* Prepare(const std::string& sql) const {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &st, nullptr) != SQLITE_OK) Fail("cannot read as a ROS 2 bag");
    return st;
  }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

class Ros2Source : public ros::BagSource {
 public:
  Ros2Source(const std::string& path, const std::vector<std::string>& files) : path_(path) {
    for (const auto& f : files) dbs_.push_back(std::make_unique<Db>(f));
    ids_.resize(dbs_.size());
    std::map<std::string, int> by_name;
    for (size_t d = 0; d < dbs_.size(); ++d) {
      const Db& db = *dbs_[d];
      sqlite3_stmt* st = db.Prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id");
      int rc;
      while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        const int id = sqlite3_column_int(st, 0);
        auto text = [&](int c) {
          const auto* p = sqlite3_column_text(st, c);
          return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
        };
        const std::string name = text(1), type = text(2), format = text(3);
        if (format != "cdr") {
          sqlite3_finalize(st);
          throw InputError(db.path() + ": topic " + name + " is serialized as '" + format + "' (cogmap reads cdr)");
        }
        auto it = by_name.find(name);
        if (it == by_name.end()) {
          it = by_name.emplace(name, static_cast<int>(topics_.size())).first;
          topics_.push_back({name, type, 0});
        } else if (topics_[it->second].type != type) {
          sqlite3_finalize(st);
          throw InputError(db.path() + ": topic " + name + " carries two types (" + topics_[it->second].type + ", " +
                           type + ")");
        }
        ids_[d][id] = it->second;
      }
      sqlite3_finalize(st);
      if (rc != SQLITE_DONE) db.Fail("cannot read the topics table");
      st = db.Prepare("SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
      while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        auto it = ids_[d].find(sqlite3_column_int(st, 0));
        if (it != ids_[d].end()) topics_[it->second].count += sqlite3_column_int64(st, 1);
      }
      sqlite3_finalize(st);
      if (rc != SQLITE_DONE) db.Fail("cannot read the messages table");
    }
  }
  ~Ros2Source() override { sqlite3_finalize(st_); }

  const std::vector<ros::TopicInfo>& topics() const override { return topics_; }

  void Start(const std::vector<int>& topics) override {
    sqlite3_finalize(st_);
    st_ = nullptr;
    wanted_ = topics;
    index_.assign(topics_.size(), 0);
    total_ = 0;
    for (int t : topics) total_ += topics_[t].count;
    done_ = 0;
    file_ = -1;
    OpenNextFile();
  }

  bool Next(ros::BagMessage* out) override {
    while (st_) {
      const int rc = sqlite3_step(st_);
      if (rc == SQLITE_ROW) {
        const int topic = ids_[file_].at(sqlite3_column_int(st_, 0));
        out->topic = topic;
        out->index = ++index_[topic];
        out->time_ns = sqlite3_column_int64(st_, 1);
        const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(st_, 2));
        const size_t size = static_cast<size_t>(sqlite3_column_bytes(st_, 2));
        try {
          out->message = cdr::Decode(ros::TypeOf(topics_[topic].type), data, size);
        } catch (const cdr::CdrError& e) {
          throw InputError(dbs_[file_]->path() + ": " + topics_[topic].name + " message " + std::to_string(out->index) +
                           ": bad CDR " + topics_[topic].type + ": " + e.what());
        }
        ++done_;
        return true;
      }
      if (rc != SQLITE_DONE)
        dbs_[file_]->Fail("cannot read the messages after message " + std::to_string(done_) + " of this pass");
      OpenNextFile();
    }
    return false;
  }

  double progress() const override { return total_ ? static_cast<double>(done_) / total_ : 1.0; }
  const std::string& path() const override { return path_; }
  std::string kind() const override { return "ROS 2 bag"; }

 private:
  void OpenNextFile() {
    sqlite3_finalize(st_);
    st_ = nullptr;
    while (++file_ < static_cast<int>(dbs_.size())) {
      std::string in;
      for (const auto& [id, t] : ids_[file_])
        if (std::find(wanted_.begin(), wanted_.end(), t) != wanted_.end()) in += (in.empty() ? "" : ",") + std::to_string(id);
      if (in.empty()) continue;
      st_ = dbs_[file_]->Prepare("SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN (" + in +
                                 ") ORDER BY timestamp, id");
      return;
    }
  }

  std::string path_;
  std::vector<std::unique_ptr<Db>> dbs_;
  std::vector<std::map<int, int>> ids_;  // per file: topic id -> index into topics_
  std::vector<ros::TopicInfo> topics_;
  std::vector<int> wanted_;
  std::vector<long> index_;
  sqlite3_stmt* st_ = nullptr;
  int file_ = -1;
  long total_ = 0, done_ = 0;
};

}  // namespace

std::unique_ptr<LogReader> OpenRos2Bag(const std::string& path, const LogOpenOptions& options) {
  std::error_code ec;
  const fs::path p(path);
  if (!fs::exists(p, ec)) throw InputError(path, 0, "cannot open: no such file or folder");
  if (p.extension() == ".mcap") McapError(path);
  fs::path folder = fs::is_directory(p, ec) ? p : p.parent_path();
  if (folder.empty()) folder = ".";
  const fs::path yaml = folder / "metadata.yaml";
  std::vector<std::string> files;
  if (fs::is_regular_file(yaml, ec)) {
    const Metadata m = ReadMetadata(yaml);
    if (m.storage == "mcap") McapError(path);
    if (m.storage != "sqlite3")
      throw InputError(yaml.string() + ": storage '" + m.storage + "': cogmap reads ROS 2 bags in the sqlite3 storage");
    if (p.extension() == ".db3") {
      files.push_back(path);
    } else {
      for (const auto& f : m.files) files.push_back((folder / f).string());
      if (files.empty()) throw InputError(yaml.string(), 0, "relative_file_paths lists no .db3 file");
    }
  } else if (p.extension() == ".db3") {
    files.push_back(path);
  } else {
    throw InputError(path, 0, "not a ROS 2 bag: no metadata.yaml and not a .db3 file");
  }
  return ros::OpenBagLog(std::make_unique<Ros2Source>(path, files), options);
}

namespace {

// A rosbag2 sqlite3 bag being written: one .db3 with rosbag2's tables (topics,
// messages), one transaction, and metadata.yaml at Close().
class Ros2BagWriter : public ros::BagWriter {
 public:
  // Writes into 'folder' the file <name>_0.db3 (rosbag2 names it after the bag).
  Ros2BagWriter(const fs::path& folder, const std::string& name) : folder_(folder), db3_(name + "_0.db3") {
    fs::create_directories(folder_);
    const std::string db_path = (folder_ / db3_).string();
    if (sqlite3_open(db_path.c_str(), &db_) != SQLITE_OK) Fail("cannot create");
    Exec("PRAGMA journal_mode=OFF");
    Exec("PRAGMA synchronous=OFF");
    Exec("CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
         "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)");
    Exec("CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
         "data BLOB NOT NULL)");
    Exec("CREATE INDEX timestamp_idx ON messages (timestamp ASC)");
    Exec("BEGIN");
    if (sqlite3_prepare_v2(db_, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1, &insert_,
                           nullptr) != SQLITE_OK)
      Fail("cannot prepare");
  }
  ~Ros2BagWriter() override {
    sqlite3_finalize(insert_);
    sqlite3_close(db_);
  }
  Ros2BagWriter(const Ros2BagWriter&) = delete;
  Ros2BagWriter& operator=(const Ros2BagWriter&) = delete;

  void Write(const std::string& topic, int64_t time_ns, const ros::Message& message) override {
    std::string type;
    const std::string data = cdr::Encode(message, &type);
    auto it = topics_.find(topic);
    if (it == topics_.end()) {
      const int id = static_cast<int>(topics_.size()) + 1;
      it = topics_.emplace(topic, Topic{id, type, 0}).first;
      sqlite3_stmt* st = nullptr;
      sqlite3_prepare_v2(db_, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", -1, &st, nullptr);
      sqlite3_bind_int(st, 1, id);
      sqlite3_bind_text(st, 2, topic.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(st, 3, type.c_str(), -1, SQLITE_TRANSIENT);
      const int rc = sqlite3_step(st);
      sqlite3_finalize(st);
      if (rc != SQLITE_DONE) Fail("cannot write the topic " + topic);
    }
    ++it->second.count;
    first_ns_ = std::min(first_ns_, time_ns);
    last_ns_ = std::max(last_ns_, time_ns);
    ++messages_;
    sqlite3_bind_int(insert_, 1, it->second.id);
    sqlite3_bind_int64(insert_, 2, time_ns);
    sqlite3_bind_blob(insert_, 3, data.data(), static_cast<int>(data.size()), SQLITE_TRANSIENT);
    if (sqlite3_step(insert_) != SQLITE_DONE) Fail("cannot write a message of " + topic);
    sqlite3_reset(insert_);
  }

  void Close() override {
    Exec("COMMIT");
    sqlite3_finalize(insert_);
    insert_ = nullptr;
    if (sqlite3_close(db_) != SQLITE_OK) Fail("cannot close");
    db_ = nullptr;
    // rosbag2's metadata (version 5: what Humble writes for sqlite3).
    const int64_t start = messages_ ? first_ns_ : 0, duration = messages_ ? last_ns_ - first_ns_ : 0;
    std::ofstream y(folder_ / "metadata.yaml");
    y << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
      << "  duration:\n    nanoseconds: " << duration << "\n  starting_time:\n    nanoseconds_since_epoch: " << start
      << "\n  message_count: " << messages_ << "\n  topics_with_message_count:\n";
    std::vector<std::pair<int, std::string>> order;
    for (const auto& [name, t] : topics_) order.push_back({t.id, name});
    std::sort(order.begin(), order.end());
    for (const auto& [id, name] : order) {
      const Topic& t = topics_.at(name);
      y << "    - topic_metadata:\n        name: " << name << "\n        type: " << t.type
        << "\n        serialization_format: cdr\n        offered_qos_profiles: \"\"\n      message_count: " << t.count
        << "\n";
    }
    y << "  compression_format: \"\"\n  compression_mode: \"\"\n  relative_file_paths:\n    - " << db3_ << "\n";
    y.close();
    if (!y) throw InputError((folder_ / "metadata.yaml").string() + ": cannot write");
  }

 private:
  struct Topic {
    int id;
    std::string type;
    long count;
  };
  void Exec(const char* sql) {
    if (sqlite3_exec(db_, sql, nullptr, nullptr, nullptr) != SQLITE_OK) Fail(sql);
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError((folder_ / db3_).string() + ": " + what + " (SQLite: " + (db_ ? sqlite3_errmsg(db_) : "") + ")");
  }

  fs::path folder_;
  std::string db3_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  std::map<std::string, Topic> topics_;
  int64_t first_ns_ = std::numeric_limits<int64_t>::max(), last_ns_ = std::numeric_limits<int64_t>::min();
  long messages_ = 0;
};

}  // namespace

long WriteRosAriaBag2(const std::string& path, const sensors::RobotDescription& robot,
                      const std::function<bool(sensors::LogRecord*)>& next) {
  std::error_code ec;
  fs::path dest = fs::path(path).lexically_normal();
  if (dest.filename().empty()) dest = dest.parent_path();
  if (fs::exists(dest, ec)) throw InputError(path, 0, "exists: a ROS 2 bag is written into a new folder");
  const fs::path tmp = dest.parent_path() / (".partial-" + dest.filename().string());
  fs::remove_all(tmp, ec);
  long records = 0;
  try {
    Ros2BagWriter bag(tmp, dest.filename().string());
    records = ros::WriteRosAriaMessages(path, robot, next, bag);
    bag.Close();
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  fs::rename(tmp, dest, ec);
  if (ec) {
    fs::remove_all(tmp, ec);
    throw InputError(path + ": cannot write (" + ec.message() + ")");
  }
  return records;
}

}  // namespace cogmap::io
