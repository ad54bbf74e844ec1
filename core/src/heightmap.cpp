#include "offsetmap/heightmap.hpp"

#include <cmath>

#include "offsetmap/error.hpp"

namespace offsetmap {

void validate_height_map(const HeightMap& map, const std::string& what) {
    if (map.width <= 0 || map.height <= 0)
        throw Error(what + " is empty (" + std::to_string(map.width) + "x" +
                    std::to_string(map.height) + ")");
    if (map.h.size() != static_cast<size_t>(map.width) * map.height)
        throw Error(what + " has " + std::to_string(map.h.size()) + " heights for " +
                    std::to_string(map.width) + "x" + std::to_string(map.height) + " texels");
    for (float v : map.h)
        if (!(v >= 0.0f && v <= 1.0f))
            throw Error(what + " has a height outside [0,1] or not finite (" + std::to_string(v) +
                        ")");
}

}  // namespace offsetmap
