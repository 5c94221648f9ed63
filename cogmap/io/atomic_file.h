#pragma once
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace cogmap::io {

// Writes 'path' all or nothing: the content goes to a temporary file beside it,
// which is renamed over 'path' only when 'write' returns without throwing and
// the stream is good. On failure the temporary file is removed, an existing
// 'path' is left as it was, and an InputError naming the path is thrown.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Same for bytes already in memory.
void WriteFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace cogmap::io
