#pragma once

namespace cogmap::asr {

// What a placer makes of a closed ASR alone, before it places it
// (CognitiveMapper::SetPlacer with a preparer; graph::MapOptimizer::Prepare).
class PlacementWork {
 public:
  virtual ~PlacementWork() = default;
};

}  // namespace cogmap::asr
