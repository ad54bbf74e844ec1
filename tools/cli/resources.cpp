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
    // On a terminal one line rewritten in place; in a log plain lines, and no blank ones.
    if (isatty(fileno(stderr)))
        std::fprintf(stderr, "\r\033[K%s", line.c_str());
    else if (!line.empty())
        std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
}

void show_progress(Runtime& runtime) {
    using Clock = std::chrono::steady_clock;
    struct State {
        Clock::time_point start, last;
        bool shown = false;
    };
    auto state = std::make_shared<State>();
    // On a terminal, one line rewritten in place after half a second; in a log, a plain line
    // every ten seconds once a step has run for two.
    const bool tty = isatty(2);
    const auto first = tty ? std::chrono::milliseconds(500) : std::chrono::milliseconds(2000);
    const auto every = tty ? std::chrono::milliseconds(100) : std::chrono::milliseconds(10000);
    runtime.set_progress([state, tty, first, every](const std::string& what, double fraction) {
        const auto now = Clock::now();
        if (fraction <= 0.0) {
            *state = {now, now - every, false};
            return;
        }
        if (fraction >= 1.0) {
            if (state->shown && tty) progress_line("");
            state->shown = false;
            return;
        }
        if (now - state->start < first || now - state->last < every) return;
        char line[256];
        std::snprintf(line, sizeof line, "%s: %3.0f%%", what.c_str(), 100.0 * fraction);
        if (tty)
            progress_line(line);
        else
            std::fprintf(stderr, "offsetmap: %s\n", line);
        state->last = now;
        state->shown = true;
    });
}

}  // namespace offsetmap::cli
