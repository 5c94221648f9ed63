#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::vectorize {

// The compact binary form of a set of polylines, whose length is the
// "polyline map" size of table 4.2 (SPEC 7).
//
// Layout (all integers LEB128 varints; signed ones zigzag-coded):
//   "CPL" 0x01                 magic and version (4 bytes)
//   quantum_mm                 coordinate step in millimetres (default 10)
//   polyline_count
//   per polyline: vertex_count, then x0 y0 (signed, in quanta), then for
//   every further vertex dx dy (signed deltas from the previous, in quanta).
// Coordinates are rounded to the nearest quantum, so a decoded vertex lies
// within quantum / 2 of the original in each axis (5 mm at the default 1 cm).
// A wall vertex costs 2-4 bytes against 4 for the int16 pair of the vertex map.
struct PolylineCodecOptions {
  int quantum_mm = 10;
};

std::string EncodePolylines(const std::vector<Polyline>& lines,
                            const PolylineCodecOptions& options = {});

// Decodes EncodePolylines' output. Throws InputError (with 'source' as the
// file name, and the byte offset) for a bad magic, a truncated varint, or
// counts that do not fit the input.
std::vector<Polyline> DecodePolylines(const std::string& bytes, const std::string& source = "<bytes>");

}  // namespace cogmap::vectorize
