#include "behind.hpp"

#include <algorithm>

namespace offsetmap::renderer {

namespace {

// The pixels whose first layer leaves them to the one behind (`needed`, in order), and the
// rectangles the second layer's planes are read from: in each band of kBand rows, runs of kBand
// columns that hold such pixels, joined across gaps of at most kGap columns.
std::vector<PixelRegion> needed_behind(const std::vector<std::uint32_t>& flags, int width,
                                       int height, std::vector<std::uint32_t>& needed) {
    constexpr int kBand = 16, kGap = 32;
    needed.clear();
    std::vector<PixelRegion> regions;
    std::vector<std::uint8_t> used((width + kBand - 1) / kBand);
    for (int band = 0; band < height; band += kBand) {
        const int rows = std::min(kBand, height - band);
        std::fill(used.begin(), used.end(), 0);
        for (int y = band; y < band + rows; ++y)
            for (int x = 0; x < width; ++x) {
                const size_t k = static_cast<size_t>(y) * width + x;
                if (!(flags[k] & OM_FLAGS_SEE_BEHIND)) continue;
                needed.push_back(static_cast<std::uint32_t>(k));
                used[x / kBand] = 1;
            }
        for (int c = 0; c < static_cast<int>(used.size()); ++c) {
            if (!used[c]) continue;
            int end = c + 1;  // one past the run's last column of kBand
            for (int next = end;
                 next < static_cast<int>(used.size()) && (next - end) * kBand <= kGap; ++next)
                if (used[next]) end = next + 1;
            const int x = c * kBand;
            regions.push_back({x, band, std::min(end * kBand, width) - x, rows});
            c = end - 1;
        }
    }
    return regions;
}

// One reconstruct launch a band (a launch costs more than the columns between runs).
std::vector<PixelRegion> bands_of(const std::vector<PixelRegion>& regions) {
    std::vector<PixelRegion> bands;
    for (const PixelRegion& r : regions) {
        if (!bands.empty() && bands.back().y == r.y)
            bands.back().width = r.x + r.width - bands.back().x;
        else
            bands.push_back(r);
    }
    return bands;
}

}  // namespace

BehindStage::BehindStage(Runtime& rt, const Scene& scene, int width, int height, bool lit)
    : rt_(rt),
      width_(width),
      height_(height),
      raster_(scene, width, height),
      planes_(rt, static_cast<size_t>(width) * height, false),
      dg_(allocate_gbuffer(rt, width, height, lit, false)),
      targets_(allocate_targets(rt, static_cast<size_t>(width) * height)),
      flags_(static_cast<size_t>(width) * height) {
    dg_.material = planes_.ids;
}

void BehindStage::trace(const View& view, const FirstLayer& first, ReconstructPass& reconstruct,
                        MaterialFrame& frame, bool curved, bool metric, bool whole,
                        Stopwatch& clock, PassTimes& t) {
    const cl::CommandQueue& q = rt_.queue();
    const size_t n = flags_.size();
    dg_.curvature = curved ? planes_.curvature : cl::Buffer();
    dg_.uv_metric = curved && metric ? planes_.uv_metric : cl::Buffer();
    q.enqueueReadBuffer(first.targets.flags, CL_TRUE, 0, n * sizeof(cl_uint), flags_.data());
    t.offset += clock.lap();
    const std::vector<PixelRegion> regions = needed_behind(flags_, width_, height_, needed_);
    if (needed_.empty() && !whole) return;
    raster_.draw_behind(view, first.raster, curved, whole ? nullptr : &needed_);
    t.gbuffer += clock.lap();
    planes_.move_from(q, raster_, n, curved, whole ? nullptr : &regions);
    if (dg_.uv_metric()) planes_.move_metric_from(q, raster_, view, n, whole ? nullptr : &regions);
    t.to_device += clock.lap();
    EngineGBuffer g2 = first.engine;
    g2.depth.buffer = planes_.depth;
    g2.normal.buffer = planes_.normal;
    g2.tangent.buffer = planes_.tangent;
    g2.uv.buffer = planes_.uv;
    if (!whole) g2.regions = bands_of(regions);
    reconstruct.enqueue(g2, dg_);
    q.finish();
    t.reconstruct += clock.lap();
    frame.enqueue_behind(first.gbuffer, first.targets, LayerBehind{dg_, targets_});
    // The depth offset's planes: the window depth and uv density of the surface shown.
    frame.take_behind(first.targets.flags, planes_.depth, first.planes.depth, n, 1);
    frame.take_behind(first.targets.flags, planes_.density, first.planes.density, n, 1);
    q.finish();
    t.offset += clock.lap();
}

}  // namespace offsetmap::renderer
