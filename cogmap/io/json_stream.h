#pragma once
// JSON written as nlohmann's dump(2) writes it, with some arrays produced one
// element at a time: a report with an entry per ASR needs no tree of every
// entry in memory (issue 14: at 1000 rooms report.json's tree was the heap's
// peak, 18 MB for a 4.5 MB file).
#include <nlohmann/json.hpp>
#include <functional>
#include <ostream>
#include <vector>

namespace cogmap::io {

class JsonStreams {
 public:
  // Sets *element to the next element and returns true, or returns false at
  // the end. Called once per element, in order, while Write runs.
  using Next = std::function<bool(nlohmann::json* element)>;

  // A placeholder to put in the document where the array goes (a string
  // only this object recognises); the array's elements come from 'next'.
  nlohmann::json Add(Next next);

  // The document with every placeholder replaced by its array, byte for
  // byte as `out << std::setw(2) << document` would write it (no newline at
  // the end). Each stream is read once.
  void Write(std::ostream& out, const nlohmann::json& document);

 private:
  void WriteValue(std::ostream& out, const nlohmann::json& v, int depth);
  int StreamOf(const nlohmann::json& v) const;  // -1: not a placeholder
  bool HoldsStream(const nlohmann::json& v) const;
  std::vector<Next> streams_;
};

}  // namespace cogmap::io
