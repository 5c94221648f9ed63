// Telling an MRPT rawlog by its first bytes (in cogmap_io: no MRPT needed).
#include <zlib.h>

#include <cctype>

#include "cogmap/io/mrpt_rawlog.h"

namespace cogmap::io {

bool LooksLikeMrptRawlogHead(std::string_view head) {
  if (head.size() < 2 || !(static_cast<unsigned char>(head[0]) & 0x80)) return false;
  const size_t len = static_cast<unsigned char>(head[0]) & 0x7F;
  if (len < 2 || len + 1 > head.size()) return false;
  // MRPT 2 writes "mrpt::obs::CObservationOdometry", MRPT 1 "CObservationOdometry".
  const std::string_view name = head.substr(1, len);
  if (name[0] != 'C' && name.rfind("mrpt::", 0) != 0) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != ':') return false;
  return true;
}

bool LooksLikeMrptRawlog(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) return false;
  char head[130];
  const int n = gzread(f, head, sizeof head);
  gzclose(f);
  return n > 0 && LooksLikeMrptRawlogHead(std::string_view(head, static_cast<size_t>(n)));
}

}  // namespace cogmap::io
