// offsetmap: the command-line front end. Each subcommand is a struct (commands.cpp, demo.cpp);
// this file parses, dispatches and turns errors into exit codes.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>
#include <new>

#include "cli.hpp"

using namespace offsetmap;
using namespace offsetmap::cli;

namespace {

// Levenshtein distance, for "did you mean".
size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
            diag = up;
        }
    }
    return row[b.size()];
}

// "" when argv names a command (or asks for help); else the one-line complaint.
std::string check_command(const CLI::App& app, int argc, char** argv) {
    std::string names, nearest;
    size_t best = 3;  // suggest only close names
    for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
        names += (names.empty() ? "" : ", ") + sub->get_name();
        if (argc > 1) {
            size_t d = edit_distance(argv[1], sub->get_name());
            if (d < best) best = d, nearest = sub->get_name();
        }
    }
    if (argc < 2) return "no command given; the commands are: " + names;
    const std::string first = argv[1];
    if (!first.empty() && first[0] == '-') return "";
    for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        if (sub->get_name() == first) return "";
    return "unknown command '" + first + "'" +
           (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
           "; the commands are: " + names;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"offsetmap: per-pixel displacement mapping as an OpenCL pass over a G-buffer"};
    app.require_subcommand(1);
    const std::vector<std::unique_ptr<Command>> commands = make_commands();
    for (const auto& c : commands) c->add_to(app);

    // Usage errors exit 2 with one line; the library's own errors exit 1 (docs/conventions.md,
    // "Exit codes").
    auto fail = [](int code, const std::string& message) {
        std::cerr << "offsetmap: error: " << message << "\n";
        return code;
    };
    if (std::string bad = check_command(app, argc, argv); !bad.empty())
        return fail(kExitUsage, bad);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
        return fail(kExitUsage,
                    std::string(e.what()) + " (see 'offsetmap " + argv[1] + " --help')");
    }
    // A bad file gives one message, the Error's, not also the decoder's own line.
    quiet_decoders(true);
    try {
        for (const auto& c : commands)
            if (*c->app) return c->run();
    } catch (const UsageError& e) {
        return fail(kExitUsage, e.what());
    } catch (const offsetmap::Error& e) {
        return fail(kExitError, e.what());
    } catch (const cl::Error& e) {
        return fail(kExitError, std::string("OpenCL call ") + e.what() +
                                    " failed: " + describe_cl_error(e.err()));
    } catch (const std::bad_alloc&) {
        return fail(kExitError, "out of memory");
    } catch (const std::exception& e) {
        return fail(kExitError, e.what());
    }
    return 0;
}
