#pragma once
// The map file: one versioned binary file holding keyframes (features, descriptors, 3D points,
// poses), submaps, loop-closure links and tagged places. Layout: magic "ASLAMMAP", uint32
// version, uint64 payload size, payload, uint32 CRC-32 of the payload (zlib). A file that is
// truncated, corrupted or of another version is rejected with a message saying which.
// (The appearance model of the loop-closure part is not in the file yet.)
#include <cstdint>
#include <map>
#include <string>
#include <vector>
#include "assistive_slam/slam_system.h"

namespace assistive_slam
{
constexpr uint32_t kMapFileVersion = 2;  ///< 2: places anchored to a keyframe

struct MapData
{
  std::vector<Keyframe> keyframes;  ///< with features
  std::vector<SubmapInfo> submaps;
  std::vector<SubmapLinkInfo> loop_links;
  std::vector<Place> places;  ///< tagged places, each on its keyframe (tag order)
};

/// The system's map as it is now (keyframes with features, submaps, loop links, places).
MapData exportMap(const SlamSystem& slam);

/// False with `err` when the file cannot be written.
bool saveMapFile(const std::string& path, const MapData& map, std::string* err);
/// False with `err` (and `map` untouched) when the file is missing, not a map file, of another
/// version, truncated or corrupted.
bool loadMapFile(const std::string& path, MapData& map, std::string* err);

}  // namespace assistive_slam
