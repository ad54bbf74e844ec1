#include "offsetmap/heightmap.hpp"

#include <atomic>
#include <cmath>

#include "offsetmap/error.hpp"

namespace offsetmap {
namespace {

std::uint64_t next_generation() {
    static std::atomic<std::uint64_t> last{0};
    return ++last;
}

}  // namespace

FieldVersion::FieldVersion() { state_.generation = next_generation(); }

FieldVersion::State FieldVersion::state() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
}

void FieldVersion::advance(const cl::Event& written) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_.generation = next_generation();
    state_.written = written;
}

void mark_changed(DeviceHeightField& f, const cl::Event& written) {
    if (!f.version) f.version = std::make_shared<FieldVersion>();
    f.ready = written;
    f.version->advance(written);
}

std::vector<cl::Event> field_ready(const DeviceHeightField& f) {
    std::vector<cl::Event> out;
    if (f.ready()) out.push_back(f.ready);
    if (f.version) {
        const cl::Event written = f.version->state().written;
        if (written() && written() != f.ready()) out.push_back(written);
    }
    return out;
}

FieldKey field_key(const DeviceHeightField& f, const std::string& detail) {
    return {f.version ? f.version->state().generation : 0, f.heights, detail};
}

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
