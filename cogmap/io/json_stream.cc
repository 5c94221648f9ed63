#include "cogmap/io/json_stream.h"

#include <string>

namespace cogmap::io {
namespace {

// The placeholder's prefix: control characters no report value holds.
const std::string kMark = std::string("\x01\x02stream:");

// 'text' (a value's dump(2)) written at 'depth': its continuation lines
// indented by two spaces per level, as a nested dump indents them.
void Indented(std::ostream& out, const std::string& text, int depth) {
  const std::string pad(2 * static_cast<size_t>(depth), ' ');
  size_t from = 0;
  for (size_t nl = text.find('\n'); nl != std::string::npos; nl = text.find('\n', from)) {
    out.write(text.data() + from, static_cast<std::streamsize>(nl + 1 - from));
    out << pad;
    from = nl + 1;
  }
  out.write(text.data() + from, static_cast<std::streamsize>(text.size() - from));
}

}  // namespace

nlohmann::json JsonStreams::Add(Next next) {
  streams_.push_back(std::move(next));
  return kMark + std::to_string(streams_.size() - 1);
}

int JsonStreams::StreamOf(const nlohmann::json& v) const {
  if (!v.is_string()) return -1;
  const auto& s = v.get_ref<const std::string&>();
  if (s.compare(0, kMark.size(), kMark) != 0) return -1;
  const int k = std::stoi(s.substr(kMark.size()));
  return k >= 0 && k < static_cast<int>(streams_.size()) ? k : -1;
}

bool JsonStreams::HoldsStream(const nlohmann::json& v) const {
  if (StreamOf(v) >= 0) return true;
  if (v.is_object() || v.is_array())
    for (const auto& e : v)
      if (HoldsStream(e)) return true;
  return false;
}

void JsonStreams::WriteValue(std::ostream& out, const nlohmann::json& v, int depth) {
  const std::string pad(2 * static_cast<size_t>(depth + 1), ' ');
  if (const int k = StreamOf(v); k >= 0) {
    nlohmann::json element;
    bool first = true;
    while (streams_[k](&element)) {
      out << (first ? "[\n" : ",\n") << pad;
      Indented(out, element.dump(2), depth + 1);
      first = false;
    }
    if (first) out << "[]";
    else out << "\n" << std::string(2 * static_cast<size_t>(depth), ' ') << "]";
    return;
  }
  if (!HoldsStream(v)) {
    Indented(out, v.dump(2), depth);
    return;
  }
  // An object or array with a stream somewhere inside: its members one by one.
  bool first = true;
  out << (v.is_object() ? "{" : "[");
  for (auto it = v.begin(); it != v.end(); ++it) {
    out << (first ? "\n" : ",\n") << pad;
    if (v.is_object()) out << nlohmann::json(it.key()).dump() << ": ";
    WriteValue(out, it.value(), depth + 1);
    first = false;
  }
  out << "\n" << std::string(2 * static_cast<size_t>(depth), ' ') << (v.is_object() ? "}" : "]");
}

void JsonStreams::Write(std::ostream& out, const nlohmann::json& document) { WriteValue(out, document, 0); }

}  // namespace cogmap::io
