// The height field on the device: heights with their box-filtered mip pyramid, and normals.
#include "offsetmap/height_field.hpp"

#include <algorithm>

#include "launch.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap {
namespace {

// The mip chain after `after`; returns the last level's event (or `after` when there is none).
std::vector<cl::Event> build_mips(Runtime& rt, DeviceHeightField& f, std::vector<cl::Event> after) {
    if (f.mip_levels < 2) return after;
    cl::Kernel k(rt.program({"prep/mips.cl"}), "om_mip_level");
    int w = f.width, h = f.height, offset = 0;
    for (int level = 1; level < f.mip_levels; ++level) {
        int cw = std::max(1, w / 2), ch = std::max(1, h / 2), child = offset + w * h;
        set_args(k, f.heights, offset, w, h, child, cw, ch);
        // Each level reads the one before it: chained by events (the queue may be out of order).
        cl::Event done;
        rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(cw, ch), cl::NullRange,
                                        &after, &done);
        after = {done};
        offset = child;
        w = cw;
        h = ch;
    }
    return after;
}

}  // namespace

int mip_level_count(int width, int height) {
    int levels = 1;
    while ((width > 1 || height > 1) && levels < OM_MAX_MIP_LEVELS) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        ++levels;
    }
    return levels;
}

size_t mip_pyramid_floats(int width, int height, int levels) {
    size_t total = 0;
    for (int k = 0; k < levels; ++k) {
        total += static_cast<size_t>(width) * height;
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
    }
    return total;
}

DeviceHeightField upload(Runtime& rt, const HeightMap& map, const PassSettings& settings,
                         const Image4* normal_map, const std::vector<cl::Event>& wait) {
    validate_height_map(map, "height map");
    validate(settings);
    if (normal_map && (normal_map->width != map.width || normal_map->height != map.height))
        throw Error("normal map is " + std::to_string(normal_map->width) + "x" +
                    std::to_string(normal_map->height) + " but the height map is " +
                    std::to_string(map.width) + "x" + std::to_string(map.height));
    DeviceHeightField f;
    f.width = map.width;
    f.height = map.height;
    const size_t n = map.h.size();
    f.mip_levels = mip_level_count(map.width, map.height);
    const std::string size = std::to_string(map.width) + "x" + std::to_string(map.height);
    f.heights =
        device_buffer(rt.context(), CL_MEM_READ_WRITE,
                      mip_pyramid_floats(map.width, map.height, f.mip_levels) * sizeof(float),
                      "the " + size + " height pyramid");
    // Level 0 through a buffer that copies the host data as it is created, so the caller's map
    // may go at once; the device copy into the pyramid is enqueued like the rest.
    cl::Buffer level0 = device_buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                      n * sizeof(float), "the " + size + " heights", map.h.data());
    cl::Event copied;
    rt.queue().enqueueCopyBuffer(level0, f.heights, 0, 0, n * sizeof(float), &wait, &copied);
    std::vector<cl::Event> done = build_mips(rt, f, {copied});
    if (normal_map) {
        f.normals = device_buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                  n * sizeof(cl_float4), "the " + size + " normal map",
                                  normal_map->texels.data());
    } else {
        f.normals = device_buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float4),
                                  "the " + size + " normals");
        cl::Kernel k(rt.program(sampling_program_files("prep/normals.cl")), "om_normals");
        set_args(k, offset_params(settings, 0, map.width, map.height), f.heights, f.normals);
        std::vector<cl::Event> after_copy = {copied};
        cl::Event normals;
        rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(map.width, map.height),
                                        cl::NullRange, &after_copy, &normals);
        done.push_back(normals);
    }
    rt.queue().enqueueMarkerWithWaitList(&done, &f.ready);
    // Submitted now, so a caller waiting on `ready` alone never waits on an unflushed queue.
    rt.queue().flush();
    return f;
}

}  // namespace offsetmap
