// The check's table on the terminal, its failure lines and its JSON.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "check.hpp"

namespace offsetmap::check {
namespace {

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += static_cast<char>(c);
        } else if (c < 0x20) {
            char esc[8];
            std::snprintf(esc, sizeof esc, "\\u%04x", c);
            out += esc;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out + "\"";
}

std::string number(double v) {
    if (!std::isfinite(v)) return "null";
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

const Fact* fact(const DeviceReport& r, const std::string& key) {
    for (const Fact& f : r.facts)
        if (f.key == key) return &f;
    return nullptr;
}

std::string value(const DeviceReport& r, const std::string& key) {
    const Fact* f = fact(r, key);
    return f ? f->value : "?";
}

}  // namespace

void collect_failures(DeviceReport& r) {
    for (const CaseResult& c : r.cases)
        if (!c.passed)
            r.failures.push_back("FAIL " + r.name + ": " + c.kernel + ", " + c.name + ": " +
                                 (c.worst_pixel.empty() ? "failed" : c.worst_pixel));
}

void print_report(const DeviceReport& r) {
    std::printf("\n%s\n", r.name.c_str());
    std::printf(
        "  %s, %s, driver %s; %s compute units at %s MHz, %s MiB, work-groups up to %s, "
        "images %s, out-of-order queue %s\n",
        value(r, "type").c_str(), value(r, "opencl").c_str(), value(r, "driver").c_str(),
        value(r, "compute_units").c_str(), value(r, "clock_mhz").c_str(),
        value(r, "global_memory_mib").c_str(), value(r, "max_work_group_size").c_str(),
        value(r, "image_support").c_str(), value(r, "out_of_order_queue").c_str());
    std::printf(
        "  the passes choose: pixels per work-item %s, heights through %s, work-groups "
        "of %s (grids %s), timed by %s; built with %s\n",
        value(r, "lanes").c_str(), value(r, "heights_path").c_str(), value(r, "local_size").c_str(),
        value(r, "grid_tile").c_str(), value(r, "timer").c_str(),
        value(r, "build_options").c_str());
    if (!r.cases.empty()) {
        std::printf("\n  %-18s %-52s %7s %10s  %s\n", "kernel", "case", "pixels", "worst",
                    "result");
        for (const CaseResult& c : r.cases) {
            std::printf("  %-18s %-52s %7zu %10.3g  %s\n", c.kernel.c_str(), c.name.c_str(),
                        c.pixels, c.worst,
                        !c.passed                         ? "FAIL"
                        : c.note.rfind("not run", 0) == 0 ? "not run"
                                                          : "ok");
        }
        std::printf(
            "  worst: the exact walks' share of their float bound against the exact hit; "
            "the others' texels from the C++ peer off the kernel's discontinuities; the "
            "material frame's pixels unlike their material's pass; shade: the colour's distance "
            "from its C++ peer off its discontinuities; reconstruct: the share of the float "
            "bound by which V and L miss the double reference\n");
    }
    if (!r.times.empty()) {
        std::printf(
            "\n  time per pixel, %s; roofline: pass-through %.3g ns/pixel, a bilinear "
            "fetch %.3g ns dependent, %.3g ns independent\n",
            r.timing_frame.c_str(), r.roof.passthrough_ns, r.roof.chain_ns, r.roof.line_ns);
        std::printf("  %-18s %12s %9s %12s %9s %10s\n", "method", "camera ns", "fetches",
                    "random ns", "fetches", "roof ns");
        for (const MethodTime& t : r.times) {
            // The time its fetches would take at the dependent-fetch rate, over the G-buffer's.
            const double roof = r.roof.passthrough_ns + t.camera_fetches * r.roof.chain_ns;
            std::printf("  %-18s %12.3g %9.3g %12.3g %9.3g %10.3g\n", t.method.c_str(), t.camera_ns,
                        t.camera_fetches, t.random_ns, t.random_fetches, roof);
        }
    }
    if (r.cases.empty()) return;  // --list
    size_t failed = 0;
    for (const CaseResult& c : r.cases) failed += !c.passed;
    std::printf("\n  %zu cases, %zu failed\n", r.cases.size(), failed);
}

std::string report_json(const std::vector<DeviceReport>& reports, const Options& o) {
    std::ostringstream j;
    size_t failures = 0;
    j << "{\n  \"check\": \"offsetmap_check\",\n  \"quick\": " << (o.quick ? "true" : "false")
      << ",\n  \"devices\": [";
    for (size_t d = 0; d < reports.size(); ++d) {
        const DeviceReport& r = reports[d];
        failures += r.failures.size();
        j << (d ? "," : "") << "\n    {\n      \"name\": " << quoted(r.name);
        for (const Fact& f : r.facts)
            j << ",\n      " << quoted(f.key) << ": " << (f.number ? f.value : quoted(f.value));
        j << ",\n      \"cases\": [";
        for (size_t k = 0; k < r.cases.size(); ++k) {
            const CaseResult& c = r.cases[k];
            j << (k ? "," : "") << "\n        {\"kernel\": " << quoted(c.kernel)
              << ", \"case\": " << quoted(c.name) << ", \"pixels\": " << c.pixels
              << ", \"passed\": " << (c.passed ? "true" : "false")
              << ", \"measure\": " << quoted(c.measure) << ", \"worst\": " << number(c.worst)
              << ", \"worst_pixel\": " << quoted(c.worst_pixel) << ", \"note\": " << quoted(c.note)
              << "}";
        }
        j << "\n      ],\n      \"timing\": {\"frame\": " << quoted(r.timing_frame)
          << ", \"roofline\": {\"passthrough_ns_per_pixel\": " << number(r.roof.passthrough_ns)
          << ", \"dependent_fetch_ns\": " << number(r.roof.chain_ns)
          << ", \"independent_fetch_ns\": " << number(r.roof.line_ns) << "}, \"methods\": [";
        for (size_t k = 0; k < r.times.size(); ++k) {
            const MethodTime& t = r.times[k];
            j << (k ? "," : "") << "\n        {\"method\": " << quoted(t.method)
              << ", \"camera_ns_per_pixel\": " << number(t.camera_ns)
              << ", \"camera_fetches_per_pixel\": " << number(t.camera_fetches)
              << ", \"random_ns_per_pixel\": " << number(t.random_ns)
              << ", \"random_fetches_per_pixel\": " << number(t.random_fetches) << "}";
        }
        j << "\n      ]},\n      \"failures\": [";
        for (size_t k = 0; k < r.failures.size(); ++k)
            j << (k ? "," : "") << "\n        " << quoted(r.failures[k]);
        j << "\n      ]\n    }";
    }
    j << "\n  ],\n  \"failures\": " << failures << "\n}\n";
    return j.str();
}

}  // namespace offsetmap::check
