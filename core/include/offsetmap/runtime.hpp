#pragma once
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"

namespace offsetmap {

// An OpenCL context, device and queue, either chosen by offsetmap or handed in by the caller, plus
// the programs built on them (cached per method and defines).
class Runtime {
  public:
    // Chooses a device: `filter` (or, when empty, $OFFSETMAP_DEVICE) is a case-insensitive
    // substring of "platform / device"; without one, the first GPU, else the first device.
    // The queue it creates has profiling on. Throws Error when nothing matches.
    static std::shared_ptr<Runtime> create(const std::string& filter = "");

    // Wraps the caller's objects; passes enqueue on `queue`. Timing needs a profiling queue on a
    // device whose profiling timestamps are a clock (probed on a queue of the runtime's own).
    Runtime(cl::Context context, cl::Device device, cl::CommandQueue queue);

    const cl::Context& context() const { return context_; }
    const cl::Device& device() const { return device_; }
    const cl::CommandQueue& queue() const { return queue_; }
    std::string device_name() const;               // "platform / device"
    bool profiling() const { return profiling_; }  // events time kernels (else no kernel times)
    bool is_pocl() const { return is_pocl_; }

    // Pixels per work-item for lane methods (kernels/common/lanes.h): 16 on PoCL's CPU device,
    // where they fill SIMD registers, 1 elsewhere (default_lanes): a GPU, and a CPU driver that
    // puts work-items in SIMD lanes itself (rusticl's llvmpipe, docs/data/bench-rusticl.md);
    // $OFFSETMAP_LANES (1, 8 or 16) or set_lanes overrides.
    int lanes() const { return lanes_; }
    void set_lanes(int lanes);

    // Whether lane methods read heights through an image (image1d_buffer view of the height
    // buffer, a GPU's texture path) instead of the buffer: on by default on GPUs with image
    // support; $OFFSETMAP_IMAGES (0 or 1) or set_images overrides. The frame is the same.
    bool images() const { return images_; }
    void set_images(bool images);
    // The defaults the constructor gives a device, before the environment's overrides.
    static int default_lanes(const cl::Device& device);
    static bool default_images(const cl::Device& device);

    // The program assembled from the shared header, then `files` (paths under kernels/) in order,
    // after `defines` ("-D" style lines are not used: `defines` is OpenCL C text). Built once.
    cl::Program program(const std::vector<std::string>& files, const std::string& defines = "");
    // Kernel `name` of a program built here; on failure an Error naming the kernel, the program's
    // files, the device and the driver's first log line.
    cl::Kernel kernel(const cl::Program& program, const std::string& name) const;
    // The text program() builds: after `defines`, the library's own offsetmap/shared.h, the
    // prelude (prelude_files) and `files`; with `pocl`, PoCL's switches first (OM_POCL: its
    // compiler builtins and target intrinsics). Kernel files from `dir` as kernel_source reads
    // them; the shared header always from the library.
    static std::string program_source(const std::vector<std::string>& files,
                                      const std::string& defines, bool pocl,
                                      const std::string& dir = "");
    // The options every program is built with: OpenCL C 1.2; on Oclgrind also unoptimised, with
    // the helpers kept as calls (OM_PLAIN_CALLS), which is what Oclgrind 21.10 can run.
    std::string build_options() const;
    // Programs built so far (each a compile; a pass's first frame after prepare adds none).
    size_t programs_built() const;
    // The compiler's warnings for the programs built so far ("files:\nlog" each); empty when
    // every one built clean. A driver that loads a program from its cache may log nothing.
    std::vector<std::string> build_warnings() const;

    // Programs built after this call read kernel files from `dir` (a copy of kernels/) instead
    // of the embedded text or $OFFSETMAP_KERNEL_DIR; empty restores those. For timing two
    // versions of a kernel in one process, in turns (offsetmap_bench --ab).
    void set_kernel_dir(const std::string& dir);

    // Progress of long steps (precomputed data): called with fraction 0 when a step starts, then
    // as it advances, and with 1 when it ends. While set, those steps run in slices and wait for
    // each one to report it; unset (the default), they are enqueued whole.
    using Progress = std::function<void(const std::string& what, double fraction)>;
    void set_progress(Progress progress) { progress_ = std::move(progress); }
    const Progress& progress() const { return progress_; }

  private:
    Progress progress_;
    cl::Context context_;
    cl::Device device_;
    cl::CommandQueue queue_;
    bool profiling_ = false;
    bool is_pocl_ = false;
    bool is_oclgrind_ = false;
    bool soft_fma_ = false;  // no fused multiply-add in hardware: the kernels' OM_SOFT_FMA
    int lanes_ = 1;
    bool images_ = false;
    mutable std::mutex mutex_;
    std::map<std::string, cl::Program> programs_;
    std::map<cl_program, std::string> names_;  // each built program's files, for errors
    std::vector<std::string> warnings_;
    std::string kernel_dir_;
};

// Every OpenCL device of every platform, as "platform / device" names; a platform without devices
// is one entry with a null device. Throws Error when the platforms cannot be listed.
struct DeviceEntry {
    cl::Platform platform;
    cl::Device device;
    std::string name;
};
std::vector<DeviceEntry> list_devices();
// The entry Runtime::create picks: the first whose name contains `filter` (case-insensitive), or
// with no filter the first GPU, else the first device; -1 when none does.
int choose_device(const std::vector<DeviceEntry>& all, const std::string& filter);

// Text of a kernel file (path relative to kernels/): read from `dir` when given, else from
// $OFFSETMAP_KERNEL_DIR when that is set (for editing kernels without rebuilding), else the text
// embedded at build time.
std::string kernel_source(const std::string& path, const std::string& dir = "");

// Milliseconds between an event's start and end (needs a profiling queue).
double event_ms(const cl::Event& event);

}  // namespace offsetmap
