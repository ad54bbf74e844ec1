// What the CLI finds beside the program (the default data, the chart scripts) and how it shows
// progress.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "cli.hpp"

#ifndef OFFSETMAP_SOURCE_DIR
#define OFFSETMAP_SOURCE_DIR ""
#endif

namespace offsetmap::cli {
namespace fs = std::filesystem;

namespace {

fs::path program_dir() {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe.parent_path();
}

}  // namespace

std::string find_beside_program(const std::string& folder, const std::string& marker,
                                const char* env) {
    std::vector<fs::path> candidates;
    if (const char* e = std::getenv(env); e && *e) candidates.emplace_back(e);
    const fs::path exe = program_dir();
    if (!exe.empty()) {
        // build/<preset>/offsetmap in a checkout; <prefix>/bin/offsetmap when installed.
        candidates.push_back(exe / ".." / ".." / folder);
        candidates.push_back(exe / ".." / "share" / "offsetmap" / folder);
    }
    // The checkout the program was built from, wherever the binary was moved to.
    if (*OFFSETMAP_SOURCE_DIR) candidates.push_back(fs::path(OFFSETMAP_SOURCE_DIR) / folder);
    std::string tried;
    for (const auto& c : candidates) {
        std::error_code ec;
        if (fs::exists(c / marker, ec)) return fs::canonical(c, ec).string();
        tried += (tried.empty() ? "" : ", ") + c.lexically_normal().string();
    }
    throw Error("cannot find the " + folder + "/ folder (looked in " + tried + "; set " + env +
                ")");
}

std::string default_data_dir() {
    return find_beside_program("data", "rocks.png", "OFFSETMAP_DATA_DIR");
}

void progress_line(const std::string& line) {
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
    std::fflush(stderr);
}

void show_progress(Runtime& runtime) {
    using Clock = std::chrono::steady_clock;
    struct State {
        Clock::time_point start;
        bool shown = false;
    };
    auto state = std::make_shared<State>();
    runtime.set_progress([state](const std::string& what, double fraction) {
        if (fraction <= 0.0) {
            *state = {Clock::now(), false};
            return;
        }
        if (fraction >= 1.0) {
            if (state->shown) progress_line(""), std::fflush(stderr);
            state->shown = false;
            return;
        }
        if (Clock::now() - state->start < std::chrono::milliseconds(500)) return;
        char line[256];
        std::snprintf(line, sizeof line, "%s: %3.0f%%", what.c_str(), 100.0 * fraction);
        progress_line(line);
        state->shown = true;
    });
}

}  // namespace offsetmap::cli
