// Opens the modules of plugin_api.h on first use and forwards the readers and
// writers declared in mrpt_rawlog.h and ros_messages.h to them.
#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "cogmap/core/error.h"
#include "cogmap/io/child_check.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/mrpt_rawlog.h"
#include "cogmap/io/plugin_api.h"
#include "cogmap/io/ros_messages.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;

// Where a module is looked for, first found first used:
//  1. $COGMAP_PLUGIN_DIR;
//  2. beside the running program: EXE_DIR/../LIBDIR/cogmap (an installed
//     PREFIX/bin/cogmap finds PREFIX/lib/cogmap; the build tree's app/cogmap
//     finds BUILD/lib/cogmap);
//  3. the install folder this cogmap was configured for;
//  4. the build tree it was built in (tests, the Python module in the build).
std::vector<std::string> ModuleDirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("COGMAP_PLUGIN_DIR"); env && *env) dirs.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back((exe.parent_path() / ".." / COGMAP_PLUGIN_LIBDIR / "cogmap").lexically_normal().string());
  for (const char* d : {COGMAP_PLUGIN_INSTALL_DIR, COGMAP_PLUGIN_BUILD_DIR})
    if (std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.emplace_back(d);
  return dirs;
}

// dlopen()s lib<name>.so from the first folder that has it and returns its
// table; throws std::runtime_error naming the module, the folders tried and
// dlerror() when none can be loaded, or the table is of another build.
template <class Table>
const Table* LoadTable(const std::string& name, const char* symbol, const std::string& what) {
  const std::string file = "lib" + name + ".so";
  std::string tried, reason = "not found";
  for (const std::string& dir : ModuleDirs()) {
    const fs::path path = fs::path(dir) / file;
    tried += (tried.empty() ? "" : ", ") + dir;
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    // RTLD_LOCAL: the module's libraries (MRPT, ROS) stay out of the global scope.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* e = dlerror();
      reason = e ? e : "dlopen failed";
      continue;
    }
    auto entry = reinterpret_cast<const Table* (*)()>(dlsym(handle, symbol));
    const Table* table = entry ? entry() : nullptr;
    if (!table) {
      reason = path.string() + " has no " + symbol;
      continue;
    }
    if (table->abi != plugin::kPluginAbi || std::string(table->version) != COGMAP_VERSION) {
      reason = path.string() + " was built for another cogmap (" + table->version + ")";
      continue;
    }
    return table;  // never closed: its code backs the objects it returns
  }
  throw std::runtime_error("cannot " + what + ": the module " + file + " could not be loaded (" + reason +
                           "; looked in " + tried + "; COGMAP_PLUGIN_DIR overrides)");
}

// The table of one module, loaded once (one module per table type); a
// failed load is tried again at the next call.
template <class Table>
const Table& Loaded(const char* name, const char* symbol, const char* what) {
  static std::once_flag once;
  static const Table* table = nullptr;
  std::call_once(once, [&] { table = LoadTable<Table>(name, symbol, what); });
  return *table;
}

const plugin::Ros1Table& Ros1() {
  return Loaded<plugin::Ros1Table>("cogmap_io_ros1", "cogmap_io_ros1_table", "read or write ROS 1 bags");
}

const plugin::MrptTable& Mrpt() {
  return Loaded<plugin::MrptTable>("cogmap_io_mrpt", "cogmap_io_mrpt_table", "read or write MRPT rawlogs");
}

}  // namespace

namespace ros {
std::unique_ptr<BagSource> OpenRos1BagSource(const std::string& path) {
  const plugin::Ros1Table& table = Ros1();
  // librosbag trusts a bag's offsets and lengths (child_check.h).
  // Every topic is read as cogmap reads it (the messages of the types it
  // decodes instantiated, the others left as they are); what the child
  // refuses with an InputError is left to this process's own reading, which
  // meets it only on the topics it reads.
  CheckInChild(path, "ROS 1 bag", "librosbag", "messages", [&](long* count) {
    const std::unique_ptr<BagSource> source = table.open_source(path);
    for (size_t t = 0; t < source->topics().size(); ++t) {
      try {
        source->Start({static_cast<int>(t)});
        BagMessage m;
        while (source->Next(&m)) ++*count;
      } catch (const InputError&) {
      }
    }
  });
  return table.open_source(path);
}
std::unique_ptr<BagWriter> MakeRos1BagWriter(const std::string& path) { return Ros1().make_writer(path); }
}  // namespace ros

std::unique_ptr<LogReader> OpenMrptRawlog(const std::string& path, const LogOpenOptions& options) {
  const plugin::MrptTable& table = Mrpt();
  // MRPT sizes its containers from a rawlog's counts (child_check.h).
  CheckInChild(path, "MRPT rawlog", "MRPT", "records", [&](long* count) {
    const std::unique_ptr<LogReader> reader = table.open(path, options);
    sensors::LogRecord record;
    while (reader->Next(&record)) ++*count;
  });
  return table.open(path, options);
}

long WriteMrptRawlog(const std::string& path, const sensors::RobotDescription& robot,
                     const std::function<bool(sensors::LogRecord*)>& next) {
  return Mrpt().write(path, robot, next);
}

}  // namespace cogmap::io
